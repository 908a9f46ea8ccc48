#include "core/image/ProjectorCorrection.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/base/Error.h"

namespace hvx::core {

ProjectorCorrection ProjectorCorrection::load(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot be read");
    std::ostringstream text;
    text << in.rdbuf();
    return parse(text.str(), path);
}

ProjectorCorrection ProjectorCorrection::parse(const std::string& json, const std::string& what) {
    using Json = nlohmann::json;
    auto fail = [&](const std::string& why) { throw Error(what + ": " + why); };
    Json j;
    try {
        j = Json::parse(json);
    } catch (const Json::exception& e) {
        fail(std::string("not valid JSON (") + e.what() + ")");
    }
    if (!j.is_object() || !j.contains("projectors") || !j["projectors"].is_array() || j["projectors"].empty())
        fail("needs a non-empty \"projectors\" list");
    ProjectorCorrection c;
    for (std::size_t i = 0; i < j["projectors"].size(); ++i) {
        const auto& p = j["projectors"][i];
        const std::string where = "projector " + std::to_string(i) + ": ";
        Entry e;
        try {
            if (p.contains("grid")) {
                e.gridW = p["grid"].at(0).get<int>();
                e.gridH = p["grid"].at(1).get<int>();
                if (e.gridW < 2 || e.gridH < 2 || e.gridW > 1024 || e.gridH > 1024) fail(where + "grid must be 2..1024 nodes a side");
                const auto& o = p.at("offsets");
                if (!o.is_array() || o.size() != std::size_t(e.gridW) * std::size_t(e.gridH))
                    fail(where + "offsets must hold grid width x height [dx, dy] pairs");
                for (const auto& d : o) {
                    const float dx = d.at(0).get<float>(), dy = d.at(1).get<float>();
                    if (!std::isfinite(dx) || !std::isfinite(dy) || std::abs(dx) > 1e4f || std::abs(dy) > 1e4f)
                        fail(where + "offsets must be finite pixel distances");
                    e.offsets.push_back({dx, dy});
                }
            }
            if (p.contains("lut")) {
                e.hasLut = true;
                const char* names[] = {"r", "g", "b"};
                for (int ch = 0; ch < 3; ++ch) {
                    const auto& t = p["lut"].at(names[ch]);
                    if (!t.is_array() || t.size() != 256) fail(where + "each lut channel needs 256 values");
                    for (std::size_t k = 0; k < 256; ++k) {
                        const float v = t[k].get<float>();
                        if (!(v >= 0.0f && v <= 1.0f)) fail(where + "lut values must be between 0 and 1");
                        e.lut[std::size_t(ch)][k] = v;
                    }
                }
            }
        } catch (const Json::exception& ex) {
            fail(where + "malformed (" + ex.what() + ")");
        }
        c.entries_.push_back(std::move(e));
    }
    return c;
}

RenderImage ProjectorCorrection::apply(const RenderImage& image, std::size_t index) const {
    if (entries_.empty()) return image;
    if (entries_.size() > 1 && index >= entries_.size()) return image;
    const Entry& e = entries_[entries_.size() == 1 ? 0 : index];
    RenderImage out = image;
    const int w = image.width, h = image.height;
    auto at = [&](const RenderImage& im, int x, int y) {
        return im.rgba[std::size_t(std::clamp(y, 0, h - 1)) * std::size_t(w) + std::size_t(std::clamp(x, 0, w - 1))];
    };
    if (!e.offsets.empty()) {
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                // The pixel's offset, bilinear between the grid nodes that span the image.
                const float gx = (float(x) + 0.5f) / float(w) * float(e.gridW - 1);
                const float gy = (float(y) + 0.5f) / float(h) * float(e.gridH - 1);
                const int x0 = std::min(int(gx), e.gridW - 2), y0 = std::min(int(gy), e.gridH - 2);
                const float fx = gx - float(x0), fy = gy - float(y0);
                auto node = [&](int i, int j) { return e.offsets[std::size_t(j) * std::size_t(e.gridW) + std::size_t(i)]; };
                float d[2];
                for (int k = 0; k < 2; ++k)
                    d[k] = (node(x0, y0)[std::size_t(k)] * (1 - fx) + node(x0 + 1, y0)[std::size_t(k)] * fx) * (1 - fy) +
                           (node(x0, y0 + 1)[std::size_t(k)] * (1 - fx) + node(x0 + 1, y0 + 1)[std::size_t(k)] * fx) * fy;
                // Bilinear sample of the input at p + offset; outside the image is black.
                const float sx = float(x) + d[0], sy = float(y) + d[1];
                glm::vec4 v(0.0f);
                if (sx >= -0.5f && sy >= -0.5f && sx <= float(w) - 0.5f && sy <= float(h) - 0.5f) {
                    const int ix = int(std::floor(sx)), iy = int(std::floor(sy));
                    const float tx = sx - float(ix), ty = sy - float(iy);
                    v = (at(image, ix, iy) * (1 - tx) + at(image, ix + 1, iy) * tx) * (1 - ty) +
                        (at(image, ix, iy + 1) * (1 - tx) + at(image, ix + 1, iy + 1) * tx) * ty;
                }
                out.rgba[std::size_t(y) * std::size_t(w) + std::size_t(x)] = v;
            }
    }
    if (e.hasLut) {
        for (auto& p : out.rgba)
            for (int ch = 0; ch < 3; ++ch) {
                const float u = std::clamp(p[ch], 0.0f, 1.0f) * 255.0f;
                const int k = std::min(int(u), 254);
                const float t = u - float(k);
                p[ch] = e.lut[std::size_t(ch)][std::size_t(k)] * (1 - t) + e.lut[std::size_t(ch)][std::size_t(k + 1)] * t;
            }
    }
    return out;
}

}  // namespace hvx::core
