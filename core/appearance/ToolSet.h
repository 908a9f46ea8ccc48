#pragma once
#include <string>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "core/camera/View.h"

namespace hvx::core {

/// The illustrative tools of a frame (thesis ch. 6 and §3.2.2) and their parameters, in patient
/// space (LPS mm) and stored values. Defaults are the thesis's. Several tools can be on at
/// once; the shader compiles a static variant per combination (variantBits()), the CPU
/// reference applies the same enhancers (core/appearance/Enhancers.glsl).
///
/// Threading: a value type.
struct ToolSet {
    /// Clip plane with view-dependent context (§6.4.1): keeps dot(normal, x) + offset <= 0.
    struct Clip {
        bool enabled = false;
        glm::dvec3 normal{0, -1, 0};
        double offset = 0;
        double thickness = 5;        ///< delta: the emphasised slab behind the cut (mm)
        double fl = 0.3, fh = 0.9;   ///< view-dependent factor ramp
    } clip;
    /// Context-preserving focal probe (§6.3): a superquadric (p, q) of `radii` about `centre`,
    /// turned by `rotationDegrees` (about the patient's x, then y, then z axis).
    struct FocalProbe {
        bool enabled = false;
        glm::dvec3 centre{0.0};
        glm::dvec3 radii{40, 40, 40};
        glm::dvec3 rotationDegrees{0.0};
        /// The probe's axes (columns) in patient space.
        glm::dmat3 rotation() const;
        /// The radius of a sphere about `centre` that holds the whole probe (pq-norm <= 1).
        double boundingRadius() const;
        double p = 2, q = 2;
        double beta = -2, rho = 0.55;
        double gl = 0.015, gh = 0.95, sl = 0.7, sh = 0.95, toon = 3;
        /// Focus and context sampling: outside the probe's bounding sphere, where it draws only
        /// the ghosted context, rays step this many samples at a time (a whole number, 1 to 8;
        /// 1: the context sampled as finely as the focus). The focus is always sampled in full.
        double contextStep = 3;
    } focal;
    /// Context-preserving probe (§6.4.2, Eqs 6.17-6.18): a sphere with a tool axis.
    struct ContextProbe {
        bool enabled = false;
        glm::dvec3 centre{0.0};
        double radius = 40;
        glm::dvec3 axis{0, -1, 0};
        double gl = 0.015, gh = 0.95;  ///< gradient filter
        double al = 0.8, ah = 1.0;     ///< axis alignment ramp (omega_a)
    } context;
    /// Band picker (§6.4.3): the trapezoid b0 <= b1 <= b2 <= b3 in stored values.
    struct Band {
        bool enabled = false;
        glm::dvec4 band{0, 0, 1, 1};
        glm::dvec3 axis{0, -1, 0};
        double al = 0.5, ah = 1.0;
    } band;
    /// Maximum importance difference accumulation (§3.2.2, Eqs 3.2-3.3): gamma 0 = plain DVR.
    struct Mimda {
        bool enabled = false;
        double gamma = 0.5;
    } mimda;

    /// True when the clip plane hides its cut-away side from every ray of `view` (seen close
    /// enough to face-on that mu = 0 at the widest ray): the working set may then skip those
    /// bricks altogether.
    bool clipHides(const View& view) const;
    /// The kept half-space as WorkingSetOptions::clipPlane expects it (dot(n, p) + d >= 0).
    glm::dvec4 keptHalfSpace() const;

    enum Bits { ClipBit = 1, FocalBit = 2, ContextBit = 4, BandBit = 8, MimdaBit = 16 };
    /// Which tools are on (the shader variant).
    int variantBits() const;
    bool any() const { return variantBits() != 0; }
    /// Throws core::Error naming the tool and the parameter outside its range.
    void validate() const;
    /// For the CLI and saved sessions.
    std::string toJson() const;
    /// Throws core::Error for malformed JSON or out-of-range values.
    static ToolSet fromJson(const std::string& json);
};

}  // namespace hvx::core
