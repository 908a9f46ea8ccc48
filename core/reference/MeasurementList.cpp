#include "core/reference/MeasurementList.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/base/Error.h"

namespace hvx::core {

namespace {
using nlohmann::json;

/// A CSV field, quoted when it holds a comma, a quote or a line break (RFC 4180).
std::string field(const std::string& s) {
    if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

std::string number(double v) {
    if (!std::isfinite(v)) return {};
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

const char* kindName(MeasureRegion::Kind k) {
    return k == MeasureRegion::Kind::Sphere    ? "sphere"
           : k == MeasureRegion::Kind::Box     ? "box"
           : k == MeasureRegion::Kind::Polygon ? "polygon"
           : k == MeasureRegion::Kind::Ellipse ? "ellipse"
           : k == MeasureRegion::Kind::Rectangle ? "rectangle"
                                               : "disc";
}

json vec(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }

glm::dvec3 vecOf(const json& j, const char* what) {
    if (!j.is_array() || j.size() != 3) throw Error(std::string("measurements: ") + what + " is not three numbers");
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}
}  // namespace

double Measurement::lengthMm() const { return kind == Kind::Distance ? glm::length(b - a) : 0.0; }

double Measurement::angleDegrees() const {
    if (kind != Kind::Angle) return 0.0;
    const glm::dvec3 u = a - b, v = c - b;
    const double lu = glm::length(u), lv = glm::length(v);
    if (lu <= 0.0 || lv <= 0.0) return 0.0;
    // atan2 of the cross and dot products: exact near 0 and 180 degrees, where acos is not.
    return glm::degrees(std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v)));
}

const char* Measurement::kindName() const {
    return kind == Kind::Distance ? "distance" : kind == Kind::Angle ? "angle" : "region";
}

const Measurement& MeasurementList::add(Measurement m) {
    m.label = "M" + std::to_string(next_++);
    items_.push_back(std::move(m));
    return items_.back();
}

bool MeasurementList::remove(const std::string& label) {
    for (auto it = items_.begin(); it != items_.end(); ++it)
        if (it->label == label) {
            items_.erase(it);
            return true;
        }
    return false;
}

void MeasurementList::clear() { items_.clear(); }

bool MeasurementList::replace(const Measurement& m) {
    for (auto& item : items_)
        if (item.label == m.label) {
            item = m;
            return true;
        }
    return false;
}

std::string MeasurementList::toCsv(const MeasurementSource& s) const {
    std::string out =
        "label,kind,view,length_mm,region,centre_x_lps,centre_y_lps,centre_z_lps,radius_mm,voxels,mean,sd,min,max,"
        "units,area_mm2,volume_mm3,exact,note,a_x_lps,a_y_lps,a_z_lps,b_x_lps,b_y_lps,b_z_lps,angle_deg,c_x_lps,c_y_lps,"
        "c_z_lps,patient_name,patient_id,study_uid,series_uid,volume,radius2_mm,spacing_assumed\n";
    for (const auto& m : items_) {
        std::vector<std::string> f{m.label, m.kindName(), m.view};
        f.push_back(m.kind == Measurement::Kind::Distance ? number(m.lengthMm()) : "");
        if (m.region) {
            f.insert(f.end(), {kindName(m.region->kind), number(m.region->centre.x), number(m.region->centre.y),
                               number(m.region->centre.z), number(m.region->radius)});
        } else {
            f.insert(f.end(), 5, "");
        }
        if (m.stats) {
            const auto& t = *m.stats;
            f.insert(f.end(), {std::to_string(t.voxels), number(t.mean), number(t.sd), number(t.min), number(t.max), t.units,
                               number(t.areaMm2), number(t.volumeMm3), t.exact ? "yes" : "no", t.note});
        } else {
            f.insert(f.end(), 10, "");
        }
        const bool points = m.kind != Measurement::Kind::Region;  // a distance's ends, an angle's end and vertex
        for (const auto& p : {m.a, m.b})
            for (int c = 0; c < 3; ++c) f.push_back(points ? number(p[c]) : "");
        const bool angle = m.kind == Measurement::Kind::Angle;
        f.push_back(angle ? number(m.angleDegrees()) : "");
        for (int c = 0; c < 3; ++c) f.push_back(angle ? number(m.c[c]) : "");
        f.insert(f.end(), {s.patientName, s.patientId, s.studyUid, s.seriesUid, s.volume});
        // An ellipse's second semi-axis (radius_mm is its first, along its axis).
        f.push_back(m.region && m.region->kind == MeasureRegion::Kind::Ellipse ? number(m.region->radius2) : "");
        f.push_back(s.spacingAssumed ? "yes: lengths are not mm" : "");
        for (std::size_t i = 0; i < f.size(); ++i) out += (i ? "," : "") + field(f[i]);
        out += "\n";
    }
    return out;
}

std::string MeasurementList::toJson(const MeasurementSource& s) const {
    json j;
    j["source"] = {{"patientName", s.patientName}, {"patientId", s.patientId}, {"studyInstanceUid", s.studyUid},
                   {"seriesInstanceUid", s.seriesUid}, {"volume", s.volume}, {"spacingAssumed", s.spacingAssumed}};
    j["coordinates"] = s.spacingAssumed ? "LPS, in units of an assumed 1 mm voxel spacing (the volume's source gave "
                                          "none): lengths, areas and volumes are not mm"
                                        : "LPS mm (DICOM patient coordinates)";
    j["measurements"] = json::array();
    for (const auto& m : items_) {
        json e = {{"label", m.label}, {"view", m.view}};
        if (m.kind == Measurement::Kind::Distance) {
            e["kind"] = "distance";
            e["a"] = vec(m.a);
            e["b"] = vec(m.b);
            e["lengthMm"] = m.lengthMm();
        } else if (m.kind == Measurement::Kind::Angle) {
            e["kind"] = "angle";
            e["a"] = vec(m.a);
            e["vertex"] = vec(m.b);
            e["c"] = vec(m.c);
            e["degrees"] = m.angleDegrees();
        } else {
            e["kind"] = "region";
        }
        if (m.region) {
            const auto& r = *m.region;
            e["region"] = {{"shape", kindName(r.kind)}, {"centre", vec(r.centre)}, {"radiusMm", r.radius},
                           {"low", vec(r.low)}, {"high", vec(r.high)}, {"normal", vec(r.normal)},
                           {"thicknessMm", r.thickness}};
            if (r.kind == MeasureRegion::Kind::Ellipse) {
                e["region"]["axis"] = vec(r.axis);
                e["region"]["radius2Mm"] = r.radius2;
            }
            if (r.outlined()) {
                e["region"]["outline"] = json::array();
                for (const auto& p : r.outline) e["region"]["outline"].push_back(vec(p));
            }
        }
        if (m.stats) {
            const auto& t = *m.stats;
            e["statistics"] = {{"voxels", t.voxels}, {"mean", t.mean}, {"sd", t.sd}, {"min", t.min}, {"max", t.max},
                               {"units", t.units}, {"areaMm2", t.areaMm2}, {"volumeMm3", t.volumeMm3},
                               {"exact", t.exact}, {"approximateVoxels", t.approximateVoxels}, {"note", t.note}};
        }
        j["measurements"].push_back(e);
    }
    return j.dump(2) + "\n";
}

MeasurementList MeasurementList::fromJson(const std::string& text) {
    MeasurementList list;
    try {
        const json j = json::parse(text);
        for (const auto& e : j.at("measurements")) {
            Measurement m;
            m.view = e.value("view", std::string());
            const std::string kind = e.at("kind").get<std::string>();
            m.kind = kind == "distance" ? Measurement::Kind::Distance
                     : kind == "angle"  ? Measurement::Kind::Angle
                     : kind == "region" ? Measurement::Kind::Region
                                        : throw Error("measurements: unknown kind '" + kind + "'");
            if (m.kind == Measurement::Kind::Distance) {
                m.a = vecOf(e.at("a"), "a distance's end");
                m.b = vecOf(e.at("b"), "a distance's end");
            } else if (m.kind == Measurement::Kind::Angle) {
                m.a = vecOf(e.at("a"), "an angle's end");
                m.b = vecOf(e.at("vertex"), "an angle's vertex");
                m.c = vecOf(e.at("c"), "an angle's end");
            }
            if (e.contains("region")) {
                const auto& r = e["region"];
                MeasureRegion g;
                const std::string shape = r.at("shape").get<std::string>();
                g.kind = shape == "sphere" ? MeasureRegion::Kind::Sphere
                         : shape == "box"  ? MeasureRegion::Kind::Box
                         : shape == "disc" ? MeasureRegion::Kind::Disc
                         : shape == "polygon" ? MeasureRegion::Kind::Polygon
                         : shape == "ellipse" ? MeasureRegion::Kind::Ellipse
                         : shape == "rectangle" ? MeasureRegion::Kind::Rectangle
                                           : throw Error("measurements: unknown region shape '" + shape + "'");
                g.centre = vecOf(r.at("centre"), "a region's centre");
                g.radius = r.at("radiusMm").get<double>();
                g.low = vecOf(r.at("low"), "a box corner");
                g.high = vecOf(r.at("high"), "a box corner");
                g.normal = vecOf(r.at("normal"), "a disc's normal");
                g.thickness = r.at("thicknessMm").get<double>();
                if (g.kind == MeasureRegion::Kind::Ellipse) {
                    g.axis = vecOf(r.at("axis"), "an ellipse's axis");
                    g.radius2 = r.at("radius2Mm").get<double>();
                }
                if (g.outlined()) {
                    for (const auto& p : r.at("outline")) g.outline.push_back(vecOf(p, "a polygon's corner"));
                    if (g.outline.size() < 3) throw Error("measurements: a polygon needs three corners or more");
                    if (g.kind == MeasureRegion::Kind::Rectangle && g.outline.size() != 4)
                        throw Error("measurements: a rectangle needs four corners");
                }
                m.region = g;
            }
            if (e.contains("statistics")) {
                const auto& t = e["statistics"];
                RegionStatistics st;
                st.voxels = t.at("voxels").get<std::uint64_t>();
                st.mean = t.at("mean").get<double>();
                st.sd = t.at("sd").get<double>();
                st.min = t.at("min").get<double>();
                st.max = t.at("max").get<double>();
                st.units = t.value("units", std::string());
                st.areaMm2 = t.value("areaMm2", 0.0);
                st.volumeMm3 = t.value("volumeMm3", 0.0);
                st.exact = t.value("exact", true);
                st.approximateVoxels = t.value("approximateVoxels", std::uint64_t(0));
                st.note = t.value("note", std::string());
                m.stats = st;
            }
            m.label = e.at("label").get<std::string>();
            if (m.label.size() > 1 && m.label[0] == 'M')  // labels stay; new ones follow the highest
                list.next_ = std::max(list.next_, std::atoi(m.label.c_str() + 1) + 1);
            list.items_.push_back(std::move(m));
        }
    } catch (const json::exception& e) {
        throw Error(std::string("measurements: not a measurement list (") + e.what() + ")");
    }
    return list;
}

}  // namespace hvx::core
