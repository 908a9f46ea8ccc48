#pragma once
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace hvx::core {

/// One view of a frame: a camera model that generates a ray per pixel, in patient (LPS, mm)
/// coordinates. Pinhole perspective and orthographic now; off-axis stereo, quilt views and the
/// light-field MCOP model are further camera models with the same interface.
struct View {
    enum class Model { Pinhole, Orthographic };
    Model model = Model::Pinhole;
    glm::dvec3 eye{0.0, -500.0, 0.0};
    glm::dvec3 target{0.0};
    glm::dvec3 up{0.0, 0.0, 1.0};
    double fovYDegrees = 30.0;   ///< pinhole
    double orthoHeight = 300.0;  ///< orthographic: mm covered by the image height
    int width = 512, height = 512;

    /// World-space ray through the centre of pixel (x, y), y = 0 at the top row.
    void ray(double x, double y, glm::dvec3& origin, glm::dvec3& direction) const;
    /// World-to-clip matrix (OpenGL conventions), for frustum tests.
    glm::dmat4 viewProjection(double nearMm = 1.0, double farMm = 1e5) const;
    /// Width in mm of one pixel at a point (its distance along the view axis for a pinhole).
    double pixelFootprint(const glm::dvec3& point) const;
    /// The same camera at `scale` times the pixel count per axis (at least 1×1): reduced
    /// resolution while interacting.
    View scaled(double scale) const;
    /// An orbit camera around `center`: azimuth 0 / elevation 0 looks from the patient's front
    /// (anterior) towards the back with superior up, so the patient's left is on the image right.
    static View orbit(const glm::dvec3& center, double radius, double azimuthDeg, double elevationDeg, int width,
                      int height, double fovYDegrees = 30.0);
};

}  // namespace hvx::core
