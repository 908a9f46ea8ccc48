#pragma once
#include <string>
#include <vector>

#include "core/image/RenderImage.h"

namespace hvx::core {

/// A Looking Glass quilt: cols x rows views in one image, view 0 (the leftmost) in the bottom-left
/// tile, then left to right and bottom to top; named with the `_qs{cols}x{rows}a{aspect}`
/// convention so players find the layout from the file name.
///
/// Threading: a value type.
struct QuiltLayout {
    int columns = 1, rows = 1, tileWidth = 1, tileHeight = 1;
    double aspect = 1.0;

    /// Top-left pixel of view i's tile in the quilt image (y down).
    void tileOrigin(int view, int& x, int& y) const;
    /// Assembles the views (each tileWidth x tileHeight) into one image; throws core::Error on
    /// a wrong count or size.
    RenderImage assemble(const std::vector<RenderImage>& views) const;
    /// "base_qs8x6a0.75.png" for base "base" (a trailing .png is replaced).
    std::string fileName(const std::string& base) const;
};

}  // namespace hvx::core
