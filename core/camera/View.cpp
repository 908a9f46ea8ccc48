#include "core/camera/View.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace hvx::core {

glm::dvec3 View::ScreenRays::normal() const { return glm::normalize(glm::cross(right, up)); }

glm::dvec3 View::ScreenRays::toPatient(const glm::dvec3& d) const {
    return centre + right * d.x + up * d.y + normal() * d.z;
}

View View::screenView(const ScreenRays& screen, int width, int height) {
    View v;
    v.model = Model::Screen;
    v.screen = screen;
    v.width = width;
    v.height = height;
    v.eye = screen.toPatient(screen.viewer);
    v.target = screen.centre;
    v.up = screen.up;
    v.fovYDegrees = glm::degrees(2.0 * std::atan(screen.heightMm / 2.0 / std::max(1e-6, screen.viewer.z)));
    return v;
}

void View::ray(double x, double y, glm::dvec3& origin, glm::dvec3& direction) const {
    if (model == Model::Screen) {
        // Eq. 5.1 with Q the screen point S: the projector's beam E->S meets the viewer line
        // z = V_z at O_x; heights and distance come from the virtual viewer V.
        const auto& s = screen;
        const glm::dvec3 S(((x + 0.5) / width - 0.5) * s.widthMm, (0.5 - (y + 0.5) / height) * s.heightMm, 0.0);
        const glm::dvec3& E = s.projector;
        const glm::dvec3& V = s.viewer;
        const double parallax = E.x + (S.x - E.x) / (S.z - E.z) * (V.z - E.z);
        const glm::dvec3 O((1.0 - s.eta) * V.x + s.eta * parallax, V.y, V.z);
        origin = s.toPatient(O);
        direction = glm::normalize(s.toPatient(S) - origin);
        return;
    }
    const glm::dvec3 f = glm::normalize(target - eye);
    const glm::dvec3 r = glm::normalize(glm::cross(f, up));
    const glm::dvec3 u = glm::cross(r, f);
    const double nx = (x + 0.5) / width * 2.0 - 1.0;
    const double ny = 1.0 - (y + 0.5) / height * 2.0;
    const double aspect = double(width) / height;
    if (model == Model::Pinhole) {
        const double th = std::tan(glm::radians(fovYDegrees) / 2.0);
        origin = eye;
        direction = glm::normalize(f + r * (nx * th * aspect) + u * (ny * th));
    } else {
        origin = eye + r * (nx * orthoHeight / 2 * aspect) + u * (ny * orthoHeight / 2);
        direction = f;
    }
}

glm::dmat4 View::viewProjection(double nearMm, double farMm) const {
    if (model == Model::Screen) {  // every point maps to the clip-space centre: nothing is culled
        glm::dmat4 keep(0.0);
        keep[3][3] = 1.0;
        return keep;
    }
    const glm::dmat4 v = glm::lookAt(eye, target, up);
    const double aspect = double(width) / height;
    glm::dmat4 p;
    if (model == Model::Pinhole) p = glm::perspective(glm::radians(fovYDegrees), aspect, nearMm, farMm);
    else p = glm::ortho(-orthoHeight / 2 * aspect, orthoHeight / 2 * aspect, -orthoHeight / 2, orthoHeight / 2, -farMm, farMm);
    return p * v;
}

double View::pixelFootprint(const glm::dvec3& point) const {
    if (model == Model::Screen) {  // a screen pixel, widened with the distance from the viewer
        const double d = glm::length(point - eye), dv = std::max(1e-6, screen.viewer.z);
        return screen.heightMm / height * d / dv;
    }
    if (model == Model::Orthographic) return orthoHeight / height;
    const double z = std::max(1e-3, glm::dot(point - eye, glm::normalize(target - eye)));
    return 2.0 * z * std::tan(glm::radians(fovYDegrees) / 2.0) / height;
}

View View::orbit(const glm::dvec3& center, double radius, double azimuthDeg, double elevationDeg, int width,
                 int height, double fovYDegrees) {
    View v;
    const double az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
    // Anterior is -y in LPS: azimuth 0 puts the eye in front of the patient.
    const glm::dvec3 dir(std::sin(az) * std::cos(el), -std::cos(az) * std::cos(el), std::sin(el));
    v.eye = center + dir * radius;
    v.target = center;
    v.up = std::abs(el) > glm::radians(89.0) ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
    v.width = width;
    v.height = height;
    v.fovYDegrees = fovYDegrees;
    return v;
}

View View::scaled(double scale) const {
    View v = *this;
    v.width = std::max(1, int(std::lround(width * scale)));
    v.height = std::max(1, int(std::lround(height * scale)));
    return v;
}

}  // namespace hvx::core
