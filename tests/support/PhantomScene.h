#pragma once
// The rendering tests' common scene: the CT phantom (96×96×80) built into an octree, a preset
// transfer function over its values and an orbit view of it (700 mm away, 30° azimuth, 20°
// elevation, 128²). Not converged until asked: some tests refine it with an accuracy of their own.
#include <string>

#include "core/appearance/TransferFunction.h"
#include "core/camera/View.h"
#include "core/volume/PhantomVoxelSource.h"
#include "tests/support/OctreeScene.h"

namespace hvx::test {

/// Holds the phantom so that it is built before the scene that reads it (base-from-member).
struct PhantomSource {
    core::PhantomVoxelSource phantom{{96, 96, 80}};
};

struct PhantomScene : private PhantomSource, OctreeScene {
    core::TransferFunction tf;
    core::View view;

    explicit PhantomScene(const std::string& preset = "ct-soft-tissue")
        : OctreeScene(phantom), tf(presetFunction(preset)), view(core::View::orbit(centre(), 700.0, 30.0, 20.0, 128, 128)) {}
    /// The transfer function `name` over the phantom's values.
    core::TransferFunction presetFunction(const std::string& name) const {
        const auto& g = reader->geometry();
        return core::TransferFunction::preset(name, g.valueMin, g.valueMax, g.rescaleSlope, g.rescaleIntercept,
                                              ws->space().minSpacing);
    }
    /// Refines and loads the cut for the view and transfer function until it settles.
    void converge() { ws->converge({view}, tf); }
};

}  // namespace hvx::test
