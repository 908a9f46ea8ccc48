#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/image/RenderImage.h"

namespace hvx::core {

/// Writes rendered frames: PNG (libpng, 8-bit, composited over black, sRGB-encoded) or OpenEXR
/// (float RGBA premultiplied, plus Z = depth in mm). Written under a temporary name and
/// renamed; throws core::Error naming the file.
class ImageWriter {
public:
    /// Picks the format from the extension (.png or .exr).
    static void write(const RenderImage& image, const std::string& path);
    static void writePng(const RenderImage& image, const std::string& path);
    /// The image libraries as linked: {"OpenEXR", "3.1.5"}, {"libpng", "1.6.39"}.
    static std::vector<std::pair<std::string, std::string>> libraryVersions();
    /// An 8-bit grey PNG of display values as they are (no sRGB encoding: a windowed slice).
    static void writeGreyPng(int width, int height, const std::vector<std::uint8_t>& grey, const std::string& path);
    /// An 8-bit RGB PNG of display colours as they are (a slice with an overlay or labels).
    static void writeRgbPng(int width, int height, const std::vector<std::uint8_t>& rgb, const std::string& path);
    static void writeExr(const RenderImage& image, const std::string& path);
    /// One OpenEXR file with one part per image (light-field views), each part named.
    static void writeExrParts(const std::vector<RenderImage>& images, const std::vector<std::string>& names,
                              const std::string& path);
};

}  // namespace hvx::core
