#pragma once
#include <vector>

#include <glm/vec3.hpp>

#include "core/appearance/TransferFunction.h"

namespace hvx::core {

/// What a user edits: a piecewise-linear opacity curve and colour stops, in stored values,
/// kept apart as in VTK, 3D Slicer and ParaView. build() merges them into a TransferFunction.
struct TransferFunctionSpec {
    struct OpacityPoint {
        double value;
        double alpha;  ///< opacity per reference length, [0, 1]
    };
    struct ColourStop {
        double value;
        glm::dvec3 rgb;  ///< [0, 1]
    };
    std::vector<OpacityPoint> opacity;
    std::vector<ColourStop> colours;
    /// Opacity scaled by gradient magnitude (TransferFunction::setGradientOpacity; |∇f| in the
    /// spec's units per mm); empty: none.
    std::vector<TransferFunction::GradientPoint> gradientOpacity;
    /// Refraction index over values (TransferFunction::setRefraction); empty: none.
    std::vector<TransferFunction::RefractionPoint> refraction;

    /// The curves of an existing transfer function (a preset).
    static TransferFunctionSpec from(const TransferFunction& tf);
    /// Opacity and colour at a value (linear between points, constant beyond the ends).
    double opacityAt(double value) const;
    glm::dvec3 colourAt(double value) const;
    /// The transfer function over [valueMin, valueMax]; throws core::Error when invalid.
    TransferFunction build(double valueMin, double valueMax, double referenceLength) const;
    /// Window/level: every point moved to centre + shift + (v - centre) · scale (scale > 0).
    TransferFunctionSpec windowed(double centre, double shift, double scale) const;
    /// Sorts the points by value; throws core::Error naming the problem (no points, values or
    /// opacities not finite, opacity or colour outside [0, 1]).
    void normalise();
};

}  // namespace hvx::core
