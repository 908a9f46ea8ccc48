#include "core/camera/OrbitCamera.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/mat3x3.hpp>

namespace hvx::core {

namespace {
glm::dquat fromAxes(const glm::dvec3& right, const glm::dvec3& up, const glm::dvec3& back) {
    return glm::normalize(glm::quat_cast(glm::dmat3(right, up, back)));
}
}  // namespace

void OrbitCamera::frame(const glm::dvec3& centre, double radius) {
    target_ = centre;
    radius_ = std::max(radius, 1e-3);
    distance_ = radius_ / std::sin(glm::radians(fovY_) / 2.0) * 1.05;
}

void OrbitCamera::setStandard(Standard s) {
    switch (s) {  // LPS: +x left, +y posterior, +z superior
    case Standard::Anterior: orientation_ = fromAxes({1, 0, 0}, {0, 0, 1}, {0, -1, 0}); break;
    case Standard::Posterior: orientation_ = fromAxes({-1, 0, 0}, {0, 0, 1}, {0, 1, 0}); break;
    case Standard::Left: orientation_ = fromAxes({0, 1, 0}, {0, 0, 1}, {1, 0, 0}); break;
    case Standard::Right: orientation_ = fromAxes({0, -1, 0}, {0, 0, 1}, {-1, 0, 0}); break;
    case Standard::Superior: orientation_ = fromAxes({-1, 0, 0}, {0, -1, 0}, {0, 0, 1}); break;
    case Standard::Inferior: orientation_ = fromAxes({1, 0, 0}, {0, -1, 0}, {0, 0, -1}); break;
    }
}

glm::dvec3 OrbitCamera::right() const { return orientation_ * glm::dvec3(1, 0, 0); }
glm::dvec3 OrbitCamera::up() const { return orientation_ * glm::dvec3(0, 1, 0); }
glm::dvec3 OrbitCamera::back() const { return orientation_ * glm::dvec3(0, 0, 1); }

void OrbitCamera::rotate(double dxPixels, double dyPixels, int viewportHeight) {
    const double perPixel = glm::pi<double>() / std::max(1, viewportHeight);
    // Dragging right turns the scene right: the camera orbits the other way about up.
    const glm::dquat yaw = glm::angleAxis(-dxPixels * perPixel, up());
    const glm::dquat pitch = glm::angleAxis(-dyPixels * perPixel, right());
    orientation_ = glm::normalize(pitch * yaw * orientation_);
}

void OrbitCamera::pan(double dxPixels, double dyPixels, int viewportHeight) {
    const double mmPerPixel = 2.0 * distance_ * std::tan(glm::radians(fovY_) / 2.0) / std::max(1, viewportHeight);
    target_ += (-dxPixels * right() + dyPixels * up()) * mmPerPixel;
}

void OrbitCamera::zoom(double factor) {
    if (factor > 0) distance_ = std::clamp(distance_ / factor, radius_ * 0.05, radius_ * 50.0);
}

View OrbitCamera::view(int width, int height) const {
    View v;
    v.model = View::Model::Pinhole;
    v.target = target_;
    v.eye = target_ + back() * distance_;
    v.up = up();
    v.fovYDegrees = fovY_;
    v.width = width;
    v.height = height;
    return v;
}

std::string OrbitCamera::patientLabel(const glm::dvec3& direction) {
    const double len = glm::length(direction);
    if (!(len > 0)) return {};
    const glm::dvec3 d = direction / len;
    std::vector<std::pair<double, char>> parts = {{std::abs(d.x), d.x > 0 ? 'L' : 'R'},
                                                  {std::abs(d.y), d.y > 0 ? 'P' : 'A'},
                                                  {std::abs(d.z), d.z > 0 ? 'S' : 'I'}};
    std::stable_sort(parts.begin(), parts.end(), [](auto& a, auto& b) { return a.first > b.first; });
    std::string label(1, parts[0].second);
    for (std::size_t i = 1; i < 3; ++i)
        if (parts[i].first > 0.3) label += parts[i].second;
    return label;
}

}  // namespace hvx::core
