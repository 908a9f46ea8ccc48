#pragma once
#include <vector>

#include "core/image/RenderImage.h"

namespace hvx::core {

/// The thesis's DVI layout for projector displays (ch. 5): each 1280x1024 frame carries 16
/// projector images of 320x240 in a 4x4 grid below a 64-row header, whose 16 blocks of 80x64
/// encode the id of the projector in each tile as a colour: R = id & 0xFF, G = id >> 8,
/// B = 255 in the written 8-bit (sRGB) PNG (a used block; unused blocks and tiles are black).
///
/// Threading: a pure function.
struct DviPacker {
    static constexpr int kFrameWidth = 1280, kFrameHeight = 1024, kTileWidth = 320, kTileHeight = 240, kHeaderRows = 64;
    /// Packs projector images (each 320x240) into ceil(n/16) frames; throws core::Error on
    /// another size.
    static std::vector<RenderImage> pack(const std::vector<RenderImage>& projectors);
    /// The projector id a header block encodes, or -1 for an unused block.
    static int decodeId(const RenderImage& frame, int tile);
    /// The linear value ImageWriter's sRGB encoding writes as `byte`, and back.
    static float linearOfByte(int byte);
    static int byteOfLinear(float linear);
};

}  // namespace hvx::core
