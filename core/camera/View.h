#pragma once
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace hvx::core {

/// One view of a frame: a camera model that generates a ray per pixel, in patient (LPS, mm)
/// coordinates. Pinhole perspective and orthographic now; off-axis stereo, quilt views and the
/// light-field MCOP model are further camera models with the same interface.
struct View {
    /// Screen: rays through a physical screen rectangle, from origins given by the multiple-
    /// centre-of-projection model of thesis Eq. 5.1; with eta = 0 it is an off-axis (shifted
    /// frustum) perspective camera at the viewer, as quilt and stereo views need.
    enum class Model { Pinhole, Orthographic, Screen };
    Model model = Model::Pinhole;
    glm::dvec3 eye{0.0, -500.0, 0.0};
    glm::dvec3 target{0.0};
    glm::dvec3 up{0.0, 0.0, 1.0};
    double fovYDegrees = 30.0;   ///< pinhole
    double orthoHeight = 300.0;  ///< orthographic: mm covered by the image height
    int width = 512, height = 512;

    /// The Screen model's geometry. Display coordinates (mm): origin at the screen centre, x
    /// right, y up, z out of the screen towards the viewer; `centre`, `right` and `up` place
    /// them in patient space.
    struct ScreenRays {
        glm::dvec3 centre{0.0}, right{1, 0, 0}, up{0, 0, 1};
        double widthMm = 500, heightMm = 300;
        glm::dvec3 viewer{0, 0, 1000};  ///< V: the (virtual) observer, display coordinates
        glm::dvec3 projector{0, 0, -1000};  ///< E: the projector emitting this view (behind: z < 0)
        double eta = 0.0;  ///< 0: perspective from V; 1: full horizontal parallax
        /// Display coordinates -> patient space.
        glm::dvec3 toPatient(const glm::dvec3& d) const;
        glm::dvec3 normal() const;
    } screen;

    /// Whether `o` is the same pinhole or orthographic camera at the same size (the rays of
    /// every pixel alike; Screen views compare as different).
    bool sameCamera(const View& o) const {
        return model == o.model && model != Model::Screen && eye == o.eye && target == o.target && up == o.up &&
               width == o.width && height == o.height && fovYDegrees == o.fovYDegrees && orthoHeight == o.orthoHeight;
    }
    /// World-space ray through the centre of pixel (x, y), y = 0 at the top row.
    void ray(double x, double y, glm::dvec3& origin, glm::dvec3& direction) const;
    /// World-to-clip matrix (OpenGL conventions), for frustum tests (the Screen model, whose
    /// origins move with the pixel, culls nothing).
    glm::dmat4 viewProjection(double nearMm = 1.0, double farMm = 1e5) const;
    /// Width in mm of one pixel at a point (its distance along the view axis for a pinhole).
    double pixelFootprint(const glm::dvec3& point) const;
    /// The same camera at `scale` times the pixel count per axis (at least 1×1): reduced
    /// resolution while interacting.
    View scaled(double scale) const;
    /// A Screen view whose rays start at `viewer` (eta 0) or follow projector `projector` (Eq.
    /// 5.1); eye/target/up are set for the working set's distance estimates.
    static View screenView(const ScreenRays& screen, int width, int height);
    /// An orbit camera around `center`: azimuth 0 / elevation 0 looks from the patient's front
    /// (anterior) towards the back with superior up, so the patient's left is on the image right.
    static View orbit(const glm::dvec3& center, double radius, double azimuthDeg, double elevationDeg, int width,
                      int height, double fovYDegrees = 30.0);
};

}  // namespace hvx::core
