#pragma once
#include <string>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "core/camera/View.h"

namespace hvx::core {

/// The 3D view's camera: an orientation (trackball), a target point and a distance, in patient
/// space (LPS mm). Standard views follow radiological conventions: anterior (the patient's left
/// on the image right, superior up), posterior, left, right, superior and inferior (anterior up;
/// the inferior view shows the patient's left on the image right, as an axial slice does).
///
/// Threading: a value type.
class OrbitCamera {
public:
    enum class Standard { Anterior, Posterior, Left, Right, Superior, Inferior };

    /// Centres on a volume of bounding radius `radius` and sees all of it.
    void frame(const glm::dvec3& centre, double radius);
    void setStandard(Standard s);
    /// Trackball: a horizontal drag turns about the view's up axis, a vertical one about its
    /// right axis; a drag across the whole viewport height turns by 180 degrees.
    void rotate(double dxPixels, double dyPixels, int viewportHeight);
    /// Moves the target in the view plane so the scene follows the pointer.
    void pan(double dxPixels, double dyPixels, int viewportHeight);
    /// factor > 1 moves closer (larger on screen).
    void zoom(double factor);
    /// The camera as a pinhole view of the given size.
    View view(int width, int height) const;

    glm::dvec3 right() const;
    glm::dvec3 up() const;
    /// From the target towards the eye.
    glm::dvec3 back() const;
    const glm::dvec3& target() const { return target_; }
    double distance() const { return distance_; }
    double fovYDegrees() const { return fovY_; }

    /// Patient-direction letters of a direction, most significant first (L/R, A/P, S/I), with a
    /// second or third letter for oblique directions (components above 0.3 of its length), as
    /// viewers label image edges: (+1, 0, 0) -> "L", (0.7, -0.7, 0) -> "LA".
    static std::string patientLabel(const glm::dvec3& direction);

private:
    glm::dquat orientation_{1, 0, 0, 0};  // camera axes (x right, y up, z back) -> patient
    glm::dvec3 target_{0.0};
    double distance_ = 500.0;
    double fovY_ = 30.0;
    double radius_ = 100.0;
};

}  // namespace hvx::core
