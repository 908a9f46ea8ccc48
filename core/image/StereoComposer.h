#pragma once
#include "core/image/RenderImage.h"
#include "core/camera/DisplayModel.h"

namespace hvx::core {

/// Combines the two views of a stereo display into its frame: side by side (left eye on the
/// left), a red-cyan anaglyph (left eye's luminance in red, right eye's green and blue), or the
/// 2-view column interleave of MedVis (even columns left eye, odd columns right eye).
///
/// Threading: a pure function.
struct StereoComposer {
    static RenderImage compose(DisplayModel::StereoLayout layout, const RenderImage& left, const RenderImage& right);
};

}  // namespace hvx::core
