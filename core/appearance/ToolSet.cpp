#include "core/appearance/ToolSet.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/constants.hpp>
#include <glm/trigonometric.hpp>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>
#include <nlohmann/json.hpp>

#include "core/appearance/Enhancers.h"
#include "core/base/Error.h"

namespace hvx::core {

namespace {
using Json = nlohmann::json;

void check(bool ok, const std::string& tool, const std::string& what) {
    if (!ok) throw Error(tool + ": " + what);
}
bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
Json vec(const glm::dvec3& v) { return Json::array({v.x, v.y, v.z}); }
glm::dvec3 vec(const Json& j, const char* tool, const char* name) {
    if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
        throw Error(std::string(tool) + ": " + name + " must be three numbers");
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}
template <class T>
T get(const Json& j, const char* key, const char* tool, T fallback) {
    if (!j.contains(key)) return fallback;
    try {
        return j.at(key).get<T>();
    } catch (const Json::exception&) {
        throw Error(std::string(tool) + ": " + key + " has the wrong type");
    }
}
}  // namespace

glm::dmat3 ToolSet::FocalProbe::rotation() const {
    const glm::dvec3 r = glm::radians(rotationDegrees);
    const glm::dmat3 rx(1, 0, 0, 0, std::cos(r.x), std::sin(r.x), 0, -std::sin(r.x), std::cos(r.x));
    const glm::dmat3 ry(std::cos(r.y), 0, -std::sin(r.y), 0, 1, 0, std::sin(r.y), 0, std::cos(r.y));
    const glm::dmat3 rz(std::cos(r.z), std::sin(r.z), 0, -std::sin(r.z), std::cos(r.z), 0, 0, 0, 1);
    return rz * ry * rx;
}

double ToolSet::FocalProbe::boundingRadius() const {
    // The unit pq-ball lies in the Euclidean ball of radius 2^(1/2 - 1/p) · 2^(1/2 - 1/q) (each
    // factor 1 for an exponent below 2: an lp norm with p <= 2 is at least the l2 norm), and in
    // the box of its radii.
    const double r = std::max({radii.x, radii.y, radii.z}) *
                     std::pow(2.0, std::max(0.0, 0.5 - 1.0 / p) + std::max(0.0, 0.5 - 1.0 / q));
    return std::min(r, glm::length(radii));
}

bool ToolSet::clipHides(const View& view) const {
    if (!clip.enabled) return false;
    const glm::dvec3 n = glm::normalize(clip.normal);
    double halfFov = 0.0;  // half the diagonal field of view: the widest ray's angle from the axis
    if (view.model == View::Model::Pinhole) {
        const double t = std::tan(glm::radians(view.fovYDegrees) / 2.0);
        halfFov = std::atan(t * std::sqrt(1.0 + double(view.width) * view.width / (double(view.height) * view.height)));
    } else if (view.model == View::Model::Screen) {
        return false;  // rays from many origins: never assume
    }
    const glm::dvec3 v = glm::normalize(view.target - view.eye);
    const double angle = std::acos(std::clamp(-glm::dot(n, v), -1.0, 1.0)) + halfFov;
    return angle < glm::pi<double>() / 2 && 1.0 - std::cos(angle) <= clip.fl;
}

glm::dvec4 ToolSet::keptHalfSpace() const {
    const double len = glm::length(clip.normal);
    return glm::dvec4(-clip.normal / len, -clip.offset / len);
}

int ToolSet::variantBits() const {
    return (clip.enabled ? ClipBit : 0) | (focal.enabled ? FocalBit : 0) | (context.enabled ? ContextBit : 0) |
           (band.enabled ? BandBit : 0) | (mimda.enabled ? MimdaBit : 0);
}

void ToolSet::validate() const {
    check(finite(clip.normal) && glm::length(clip.normal) > 1e-9 && std::isfinite(clip.offset), "clip plane",
          "the normal must be a non-zero vector and the offset finite");
    check(clip.thickness >= 0 && clip.thickness <= 1000, "clip plane", "thickness must be between 0 and 1000 mm");
    check(clip.fl >= 0 && clip.fl < clip.fh && clip.fh <= 1, "clip plane", "need 0 <= fl < fh <= 1");
    check(finite(focal.centre) && focal.radii.x > 0 && focal.radii.y > 0 && focal.radii.z > 0 && finite(focal.radii),
          "focal probe", "the radii must be positive");
    check(finite(focal.rotationDegrees) && glm::all(glm::lessThanEqual(glm::abs(focal.rotationDegrees), glm::dvec3(360.0))),
          "focal probe", "rotations must be between -360 and 360 degrees");
    check(focal.p >= 0.5 && focal.p <= 64 && focal.q >= 0.5 && focal.q <= 64, "focal probe", "p and q must be between 0.5 and 64");
    check(focal.beta >= -20 && focal.beta <= 20, "focal probe", "beta must be between -20 and 20");
    check(focal.rho >= 0 && focal.rho < 1, "focal probe", "rho must be in [0, 1)");
    check(focal.gl >= 0 && focal.gl < focal.gh && focal.gh <= 1, "focal probe", "need 0 <= g_l < g_h <= 1");
    check(focal.sl >= 0 && focal.sl < focal.sh && focal.sh <= 1, "focal probe", "need 0 <= s_l < s_h <= 1");
    check(focal.toon >= 0 && focal.toon <= 20, "focal probe", "the toon factor a must be between 0 and 20");
    check(focal.contextStep >= 1 && focal.contextStep <= 8 && focal.contextStep == std::floor(focal.contextStep),
          "focal probe", "the context step must be a whole number of samples from 1 to 8");
    check(finite(context.centre) && context.radius > 0 && std::isfinite(context.radius), "context probe",
          "the radius must be positive");
    check(finite(context.axis) && glm::length(context.axis) > 1e-9, "context probe", "the axis must be non-zero");
    check(context.gl >= 0 && context.gl < context.gh && context.gh <= 1, "context probe", "need 0 <= g_l < g_h <= 1");
    check(context.al >= 0 && context.al < context.ah && context.ah <= 1, "context probe", "need 0 <= a_l < a_h <= 1");
    check(band.band.x <= band.band.y && band.band.y <= band.band.z && band.band.z <= band.band.w && std::isfinite(band.band.x) &&
              std::isfinite(band.band.w),
          "band picker", "the band needs b0 <= b1 <= b2 <= b3");
    check(finite(band.axis) && glm::length(band.axis) > 1e-9, "band picker", "the axis must be non-zero");
    check(band.al >= 0 && band.al < band.ah && band.ah <= 1, "band picker", "need 0 <= a_l < a_h <= 1");
    check(mimda.gamma >= 0 && mimda.gamma <= 1, "MImDA", "gamma must be between 0 and 1");
}

std::string ToolSet::toJson() const {
    Json j;
    j["clip"] = {{"enabled", clip.enabled}, {"normal", vec(clip.normal)}, {"offset", clip.offset},
                 {"thickness", clip.thickness}, {"fl", clip.fl}, {"fh", clip.fh}};
    j["focal"] = {{"enabled", focal.enabled}, {"centre", vec(focal.centre)}, {"radii", vec(focal.radii)},
                  {"rotationDegrees", vec(focal.rotationDegrees)}, {"p", focal.p}, {"q", focal.q}, {"beta", focal.beta}, {"rho", focal.rho},
                  {"gl", focal.gl}, {"gh", focal.gh}, {"sl", focal.sl}, {"sh", focal.sh}, {"toon", focal.toon},
                  {"contextStep", focal.contextStep}};
    j["context"] = {{"enabled", context.enabled}, {"centre", vec(context.centre)}, {"radius", context.radius},
                    {"axis", vec(context.axis)}, {"gl", context.gl}, {"gh", context.gh}, {"al", context.al},
                    {"ah", context.ah}};
    j["band"] = {{"enabled", band.enabled}, {"band", {band.band.x, band.band.y, band.band.z, band.band.w}},
                 {"axis", vec(band.axis)}, {"al", band.al}, {"ah", band.ah}};
    j["mimda"] = {{"enabled", mimda.enabled}, {"gamma", mimda.gamma}};
    return j.dump(2);
}

ToolSet ToolSet::fromJson(const std::string& text) {
    Json j;
    try {
        j = Json::parse(text);
    } catch (const Json::exception& e) {
        throw Error(std::string("tools: not valid JSON (") + e.what() + ")");
    }
    ToolSet t;
    if (j.contains("clip")) {
        const auto& c = j["clip"];
        t.clip.enabled = get(c, "enabled", "clip plane", false);
        if (c.contains("normal")) t.clip.normal = vec(c["normal"], "clip plane", "normal");
        t.clip.offset = get(c, "offset", "clip plane", t.clip.offset);
        t.clip.thickness = get(c, "thickness", "clip plane", t.clip.thickness);
        t.clip.fl = get(c, "fl", "clip plane", t.clip.fl);
        t.clip.fh = get(c, "fh", "clip plane", t.clip.fh);
    }
    if (j.contains("focal")) {
        const auto& f = j["focal"];
        t.focal.enabled = get(f, "enabled", "focal probe", false);
        if (f.contains("centre")) t.focal.centre = vec(f["centre"], "focal probe", "centre");
        if (f.contains("radii")) t.focal.radii = vec(f["radii"], "focal probe", "radii");
        if (f.contains("rotationDegrees")) t.focal.rotationDegrees = vec(f["rotationDegrees"], "focal probe", "rotationDegrees");
        for (auto [key, field] : {std::pair{"p", &t.focal.p}, {"q", &t.focal.q}, {"beta", &t.focal.beta}, {"rho", &t.focal.rho},
                                  {"gl", &t.focal.gl}, {"gh", &t.focal.gh}, {"sl", &t.focal.sl}, {"sh", &t.focal.sh},
                                  {"toon", &t.focal.toon}, {"contextStep", &t.focal.contextStep}})
            *field = get(f, key, "focal probe", *field);
    }
    if (j.contains("context")) {
        const auto& c = j["context"];
        t.context.enabled = get(c, "enabled", "context probe", false);
        if (c.contains("centre")) t.context.centre = vec(c["centre"], "context probe", "centre");
        if (c.contains("axis")) t.context.axis = vec(c["axis"], "context probe", "axis");
        for (auto [key, field] : {std::pair{"radius", &t.context.radius}, {"gl", &t.context.gl}, {"gh", &t.context.gh},
                                  {"al", &t.context.al}, {"ah", &t.context.ah}})
            *field = get(c, key, "context probe", *field);
    }
    if (j.contains("band")) {
        const auto& b = j["band"];
        t.band.enabled = get(b, "enabled", "band picker", false);
        if (b.contains("band")) {
            if (!b["band"].is_array() || b["band"].size() != 4) throw Error("band picker: band must be four values");
            for (int k = 0; k < 4; ++k) t.band.band[k] = b["band"][std::size_t(k)].get<double>();
        }
        if (b.contains("axis")) t.band.axis = vec(b["axis"], "band picker", "axis");
        t.band.al = get(b, "al", "band picker", t.band.al);
        t.band.ah = get(b, "ah", "band picker", t.band.ah);
    }
    if (j.contains("mimda")) {
        t.mimda.enabled = get(j["mimda"], "enabled", "MImDA", false);
        t.mimda.gamma = get(j["mimda"], "gamma", "MImDA", t.mimda.gamma);
    }
    t.validate();
    return t;
}

glsl::HvxTools packTools(const ToolSet& t, const glm::dvec4& shading) {
    glsl::HvxTools p{};
    const glm::dvec3 n = glm::normalize(t.clip.normal);
    p.clipPlane = glm::vec4(glm::vec3(n), float(t.clip.offset / glm::length(t.clip.normal)));
    p.clipParams = glm::vec4(float(t.clip.thickness), float(t.clip.fl), float(t.clip.fh), 0.0f);
    p.focalCentre = glm::vec4(glm::vec3(t.focal.centre), float(t.focal.p));
    p.focalRadii = glm::vec4(glm::vec3(t.focal.radii), float(t.focal.q));
    const glm::dmat3 rotation = t.focal.rotation();
    p.focalRot0 = glm::vec4(glm::vec3(rotation[0]), float(t.focal.contextStep));
    p.focalRot1 = glm::vec4(glm::vec3(rotation[1]), 0.0f);
    p.focalRot2 = glm::vec4(glm::vec3(rotation[2]), 0.0f);
    p.focalParams = glm::vec4(float(t.focal.beta), float(t.focal.rho), float(t.focal.gl), float(t.focal.gh));
    p.focalStyle = glm::vec4(float(t.focal.sl), float(t.focal.sh), float(t.focal.toon), float(t.focal.boundingRadius()));
    p.contextCentre = glm::vec4(glm::vec3(t.context.centre), float(t.context.radius));
    p.contextAxis = glm::vec4(glm::vec3(glm::normalize(t.context.axis)), 0.0f);
    p.contextParams = glm::vec4(float(t.context.gl), float(t.context.gh), float(t.context.al), float(t.context.ah));
    p.band = glm::vec4(t.band.band);
    p.bandAxis = glm::vec4(glm::vec3(glm::normalize(t.band.axis)), float(t.mimda.enabled ? t.mimda.gamma : 0.0));
    p.bandParams = glm::vec4(float(t.band.al), float(t.band.ah), 0.0f, 0.0f);
    p.shading = glm::vec4(shading);
    return p;
}

}  // namespace hvx::core
