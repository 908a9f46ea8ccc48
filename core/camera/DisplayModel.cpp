#include "core/camera/DisplayModel.h"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include "core/base/Error.h"

namespace hvx::core {

const std::map<std::string, std::string>& embeddedDisplayProfiles();  // generated at build time

namespace {
using Json = nlohmann::json;

struct Reader {
    const Json& j;
    const std::string& what;
    [[noreturn]] void fail(const std::string& field, const std::string& why) const {
        throw Error("display profile " + what + ": " + field + " " + why);
    }
    double number(const char* field, double lo, double hi) const {
        if (!j.contains(field)) fail(field, "is missing");
        if (!j[field].is_number()) fail(field, "must be a number");
        const double v = j[field].get<double>();
        if (!(v >= lo && v <= hi)) fail(field, "must be between " + std::to_string(lo) + " and " + std::to_string(hi));
        return v;
    }
    double number(const char* field, double lo, double hi, double fallback) const {
        return j.contains(field) ? number(field, lo, hi) : fallback;
    }
    std::pair<double, double> pair(const char* field, double lo, double hi) const {
        if (!j.contains(field) || !j[field].is_array() || j[field].size() != 2 || !j[field][0].is_number() ||
            !j[field][1].is_number())
            fail(field, "must be a pair of numbers [a, b]");
        const double a = j[field][0].get<double>(), b = j[field][1].get<double>();
        if (!(a >= lo && a <= hi && b >= lo && b <= hi))
            fail(field, "must hold values between " + std::to_string(lo) + " and " + std::to_string(hi));
        return {a, b};
    }
    std::string text(const char* field) const {
        if (!j.contains(field) || !j[field].is_string()) fail(field, "must be a string");
        return j[field].get<std::string>();
    }
};
}  // namespace

std::vector<std::string> DisplayModel::builtInNames() {
    std::vector<std::string> names;
    for (const auto& [file, text] : embeddedDisplayProfiles()) names.push_back(file.substr(0, file.size() - 5));
    return names;
}

DisplayModel DisplayModel::load(const std::string& nameOrPath) {
    const auto& builtIn = embeddedDisplayProfiles();
    if (const auto it = builtIn.find(nameOrPath + ".json"); it != builtIn.end()) return parse(it->second, nameOrPath);
    std::ifstream in(nameOrPath, std::ios::binary);
    if (!in) {
        std::string known;
        for (const auto& n : builtInNames()) known += (known.empty() ? "" : ", ") + n;
        throw Error("display profile '" + nameOrPath + "' is neither a built-in profile (" + known + ") nor a readable file");
    }
    std::ostringstream text;
    text << in.rdbuf();
    if (text.str().size() > (1u << 20)) throw Error("display profile " + nameOrPath + " is too large");
    return parse(text.str(), nameOrPath);
}

DisplayModel DisplayModel::parse(const std::string& json, const std::string& what) {
    Json j;
    try {
        j = Json::parse(json);
    } catch (const Json::exception& e) {
        throw Error("display profile " + what + " is not valid JSON (" + e.what() + ")");
    }
    if (!j.is_object()) throw Error("display profile " + what + " must be a JSON object");
    const Reader r{j, what};
    DisplayModel d;
    d.name = j.contains("name") ? r.text("name") : what;
    const std::string kind = r.text("kind");
    const auto screen = r.pair("screenSizeMm", 1, 100000);
    d.screenWidthMm = screen.first;
    d.screenHeightMm = screen.second;
    d.observerDistanceMm = r.number("observerDistanceMm", 10, 100000, 1000);
    d.observerHeightMm = r.number("observerHeightMm", -100000, 100000, 0);
    if (kind == "projector-array") {
        d.kind = Kind::ProjectorArray;
        d.projectors = int(r.number("projectors", 1, 4096));
        const auto res = r.pair("projectorResolution", 1, 16384);
        d.projectorWidth = int(res.first);
        d.projectorHeight = int(res.second);
        d.pixelSizeMm = r.number("pixelSizeMm", 1e-3, 1000);
        d.beamAngleDegrees = r.number("beamAngleDegrees", 1e-3, 45);
        d.fieldOfViewDegrees = r.number("fieldOfViewDegrees", 1, 170);
        d.projectorDistanceMm = r.number("projectorDistanceMm", 1, 100000);
    } else if (kind == "lenticular") {
        d.kind = Kind::Lenticular;
        const auto quilt = r.pair("quilt", 1, 64);
        d.quiltColumns = int(quilt.first);
        d.quiltRows = int(quilt.second);
        const auto size = r.pair("quiltSize", 1, 16384);
        d.quiltWidth = int(size.first);
        d.quiltHeight = int(size.second);
        if (d.quiltWidth < d.quiltColumns || d.quiltHeight < d.quiltRows)
            r.fail("quiltSize", "is too small for " + std::to_string(d.quiltColumns) + "x" + std::to_string(d.quiltRows) + " views");
        d.aspect = r.number("aspect", 0.05, 20);
        d.viewConeDegrees = r.number("viewConeDegrees", 1, 170);
    } else if (kind == "stereo") {
        d.kind = Kind::Stereo;
        const std::string layout = r.text("layout");
        if (layout == "side-by-side") d.layout = StereoLayout::SideBySide;
        else if (layout == "anaglyph") d.layout = StereoLayout::Anaglyph;
        else if (layout == "column-interleave") d.layout = StereoLayout::ColumnInterleave;
        else r.fail("layout", "must be side-by-side, anaglyph or column-interleave");
        const auto size = r.pair("viewSize", 1, 16384);
        d.viewWidth = int(size.first);
        d.viewHeight = int(size.second);
        d.eyeSeparationMm = r.number("eyeSeparationMm", 1, 1000);
    } else {
        r.fail("kind", "must be projector-array, lenticular or stereo (not '" + kind + "')");
    }
    return d;
}

int DisplayModel::viewCount() const {
    switch (kind) {
    case Kind::ProjectorArray: return projectors;
    case Kind::Lenticular: return quiltColumns * quiltRows;
    case Kind::Stereo: break;
    }
    return 2;
}

int DisplayModel::viewWidthPx() const {
    return kind == Kind::ProjectorArray ? projectorWidth : kind == Kind::Lenticular ? quiltWidth / quiltColumns : viewWidth;
}

int DisplayModel::viewHeightPx() const {
    return kind == Kind::ProjectorArray ? projectorHeight : kind == Kind::Lenticular ? quiltHeight / quiltRows : viewHeight;
}

glm::dvec3 DisplayModel::projectorPosition(int i) const {
    // Evenly spaced on a line behind the screen, spanning the field of view seen from the centre.
    const double span = 2.0 * projectorDistanceMm * std::tan(glm::radians(fieldOfViewDegrees) / 2.0);
    return {(double(i) + 0.5 - projectors / 2.0) * span / projectors, 0.0, -projectorDistanceMm};
}

std::vector<View> DisplayModel::views(const glm::dvec3& centre, const glm::dvec3& right, const glm::dvec3& up, double eta,
                                      int widthOverride, int heightOverride, double scale, double depthScale) const {
    if (!(eta >= 0.0 && eta <= 1.0)) throw Error("eta must be between 0 and 1");
    if (depthScale == 0.0) depthScale = scale;
    if (!(scale > 0.0 && std::isfinite(scale)) || !(depthScale > 0.0 && std::isfinite(depthScale)))
        throw Error("the display scale must be positive");
    const int w = widthOverride > 0 ? widthOverride : viewWidthPx(), h = heightOverride > 0 ? heightOverride : viewHeightPx();
    if (w < 1 || h < 1 || std::int64_t(w) * h * viewCount() > (std::int64_t(1) << 31))
        throw Error("impossible view size " + std::to_string(w) + "x" + std::to_string(h) + " for " +
                    std::to_string(viewCount()) + " views");
    View::ScreenRays s;
    s.centre = centre;
    s.right = glm::normalize(right);
    s.up = glm::normalize(up - glm::dot(up, s.right) * s.right);
    // Display lengths in patient mm: divided by the scale, across the screen and along its
    // normal. Display space maps to patient space linearly, so its straight rays stay straight:
    // viewers and projectors placed by the two scales give the rays of the compressed display.
    const glm::dvec3 toPatient(1.0 / scale, 1.0 / scale, 1.0 / depthScale);
    s.widthMm = screenWidthMm / scale;
    s.heightMm = screenHeightMm / scale;
    s.viewer = glm::dvec3(0.0, observerHeightMm, observerDistanceMm) * toPatient;
    std::vector<View> out;
    const int n = viewCount();
    for (int i = 0; i < n; ++i) {
        View::ScreenRays v = s;
        if (kind == Kind::ProjectorArray) {
            v.projector = projectorPosition(i) * toPatient;
            v.eta = eta;
        } else {
            // Off-axis cameras on the viewing line, leftmost first: a shifted frustum through
            // the same screen rectangle (never toed in).
            const double half = kind == Kind::Lenticular ? std::tan(glm::radians(viewConeDegrees) / 2.0) * observerDistanceMm
                                                          : eyeSeparationMm / 2.0;
            const double t = n > 1 ? double(i) / double(n - 1) : 0.5;
            v.viewer.x = (-half + 2.0 * half * t) / scale;
            v.eta = 0.0;
        }
        out.push_back(View::screenView(v, w, h));
    }
    return out;
}

double DisplayModel::accuracy(double zMm) const {
    const double s0 = kind == Kind::ProjectorArray ? pixelSizeMm : screenHeightMm / std::max(1, viewHeightPx());
    const double phi = kind == Kind::ProjectorArray ? beamAngleDegrees
                       : kind == Kind::Lenticular   ? viewConeDegrees / std::max(1, viewCount() - 1)
                                                    : 2.0 * glm::degrees(std::atan(eyeSeparationMm / 2.0 / observerDistanceMm));
    return s0 + 2.0 * std::abs(zMm) * std::tan(glm::radians(phi) / 2.0);
}

double DisplayModel::depthRangeMm() const {
    // s(z) = s0 + 2|z| tan(phi/2) is linear in |z|: twice s0 at s0 / (s'(z)).
    const double s0 = accuracy(0.0), slope = accuracy(1000.0) - s0;  // per metre
    return slope > 0 ? s0 / slope * 1000.0 : 1e9;
}

DisplayModel::Framing DisplayModel::frame(const std::vector<glm::dvec3>& points, const glm::dvec3& right,
                                          const glm::dvec3& up, bool trueDepth) const {
    Framing f;
    if (points.empty()) return f;
    const glm::dvec3 axes[3] = {glm::normalize(right), glm::normalize(up), glm::normalize(glm::cross(right, up))};
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& p : points)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], glm::dot(p, axes[a]));
            hi[a] = std::max(hi[a], glm::dot(p, axes[a]));
        }
    const glm::dvec3 mid = 0.5 * (lo + hi), extent = glm::max(hi - lo, glm::dvec3(1e-6));
    f.centre = mid.x * axes[0] + mid.y * axes[1] + mid.z * axes[2];
    constexpr double kMargin = 0.95;  // a rim of screen around the content
    const double byWidth = kMargin * screenWidthMm / extent.x, byHeight = kMargin * screenHeightMm / extent.y;
    const double byDepth = 2.0 * depthRangeMm() / extent.z;  // half the depth either side of the screen
    f.scale = std::min(byWidth, byHeight);
    f.limit = byHeight < byWidth ? "height" : "width";
    f.depthScale = std::min(f.scale, byDepth);
    if (trueDepth) f.scale = f.depthScale;
    return f;
}

AccuracyFunction DisplayModel::accuracyFunction(double scale, double depthScale) const {
    const DisplayModel self = *this;
    if (depthScale == 0.0) depthScale = scale;
    return [self, scale, depthScale](const View& view, const glm::dvec3& point) {
        const double z = glm::dot(point - view.screen.centre, view.screen.normal()) * depthScale;  // display mm
        return self.accuracy(z) / scale;
    };
}

}  // namespace hvx::core
