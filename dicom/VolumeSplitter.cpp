#include "dicom/VolumeSplitter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <set>

#include <glm/geometric.hpp>

namespace hvx::dicom {

namespace {

const FrameGeometry& frameOf(const std::vector<DicomInstance>& instances, const VolumeSplitter::Member& m) {
    const auto& in = instances[m.first];
    return in.frame(m.second);
}

std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", v);
    return b;
}

/// One way images at a position may differ: a sortable key and its words.
struct Dimension {
    const char* name;
    std::function<std::pair<std::string, std::string>(const FrameDimensions&)> keyAndWords;
};

std::string padded(double v) {  // a key that sorts numerically as text
    char b[48];
    std::snprintf(b, sizeof b, "%020.6f", v + 1e9);
    return b;
}

const std::vector<Dimension>& dimensions() {
    static const std::vector<Dimension> d = {
        {"image type", [](const FrameDimensions& f) { return std::make_pair(f.imageType, f.imageType); }},
        {"echo",
         [](const FrameDimensions& f) {
             const std::string te = f.echoTime ? " (TE " + num(*f.echoTime) + " ms)" : "";
             // Both: echoes numbered alike but of different TE are two echoes (seen in the field);
             // TE to 0.01 ms, so that jitter in its last digits does not split an echo.
             if (f.echoNumber)
                 return std::make_pair(padded(*f.echoNumber) + (f.echoTime ? padded(std::round(*f.echoTime * 100.0) / 100.0) : std::string()),
                                       "echo " + std::to_string(*f.echoNumber) + te);
             if (f.echoTime) return std::make_pair(padded(*f.echoTime), "TE " + num(*f.echoTime) + " ms");
             return std::make_pair(std::string(), std::string());
         }},
        {"diffusion",
         [](const FrameDimensions& f) {
             std::string key, words;
             if (f.bValue) {
                 key = padded(*f.bValue);
                 words = "b " + num(*f.bValue);
             }
             if (f.gradient && f.bValue && *f.bValue > 0) {
                 const auto& g = *f.gradient;
                 key += padded(std::round(g.x * 1e4)) + padded(std::round(g.y * 1e4)) + padded(std::round(g.z * 1e4));
                 words += " (" + num(g.x) + ", " + num(g.y) + ", " + num(g.z) + ")";
             }
             return std::make_pair(key, words);
         }},
        {"time point",
         [](const FrameDimensions& f) {
             if (!f.temporalPosition) return std::make_pair(std::string(), std::string());
             return std::make_pair(padded(*f.temporalPosition), "time " + std::to_string(*f.temporalPosition));
         }},
        {"trigger time",
         [](const FrameDimensions& f) {
             if (!f.triggerTime) return std::make_pair(std::string(), std::string());
             return std::make_pair(padded(*f.triggerTime), "trigger " + num(*f.triggerTime) + " ms");
         }},
        {"acquisition",
         [](const FrameDimensions& f) {
             if (!f.acquisitionNumber) return std::make_pair(std::string(), std::string());
             return std::make_pair(padded(*f.acquisitionNumber), "acquisition " + std::to_string(*f.acquisitionNumber));
         }},
        {"stack", [](const FrameDimensions& f) { return std::make_pair(f.stackId, f.stackId.empty() ? "" : "stack " + f.stackId); }},
    };
    return d;
}

/// The positions along the normal of the members that have one, sorted.
std::vector<double> positionsAlong(const std::vector<DicomInstance>& instances,
                                   const std::vector<VolumeSplitter::Member>& m, const glm::dvec3& normal) {
    std::vector<double> along;
    for (const auto& member : m) {
        const auto& fg = frameOf(instances, member);
        if (fg.hasPosition) along.push_back(glm::dot(fg.position, normal));
    }
    std::sort(along.begin(), along.end());
    return along;
}

/// Frames at positions held by more than one frame: positions closer than `tolerance` mm along
/// the normal are one position.
std::size_t repeatedPositions(const std::vector<DicomInstance>& instances, const std::vector<VolumeSplitter::Member>& m,
                              const glm::dvec3& normal, double tolerance) {
    const auto along = positionsAlong(instances, m, normal);
    std::size_t repeated = 0, run = 1;
    for (std::size_t i = 1; i <= along.size(); ++i) {
        if (i < along.size() && along[i] - along[i - 1] <= tolerance) {
            ++run;
            continue;
        }
        if (run > 1) repeated += run;
        run = 1;
    }
    return repeated;
}

/// How many distinct positions (closer than `tolerance` mm are one) the members hold.
std::size_t distinctPositions(const std::vector<DicomInstance>& instances, const std::vector<VolumeSplitter::Member>& m,
                              const glm::dvec3& normal, double tolerance) {
    const auto along = positionsAlong(instances, m, normal);
    std::size_t n = along.empty() ? 0 : 1;
    for (std::size_t i = 1; i < along.size(); ++i) n += along[i] - along[i - 1] > tolerance ? 1 : 0;
    return n;
}

/// Whether the members' positions are evenly spaced (to a hundredth of the spacing), as
/// SeriesAssembler takes a stack to be without resampling it.
bool evenlySpaced(const std::vector<DicomInstance>& instances, const std::vector<VolumeSplitter::Member>& m,
                  const glm::dvec3& normal) {
    const auto along = positionsAlong(instances, m, normal);
    if (along.size() < 3) return true;
    std::vector<double> gaps;
    for (std::size_t i = 1; i < along.size(); ++i) gaps.push_back(along[i] - along[i - 1]);
    std::sort(gaps.begin(), gaps.end());
    return gaps.back() - gaps.front() <= std::max(0.01 * gaps[gaps.size() / 2], 1e-3);
}

/// The part's members grouped by one dimension's value (sorted by key), each named.
std::vector<VolumeSplitter::Part> splitBy(const std::vector<DicomInstance>& instances, const VolumeSplitter::Part& part,
                                          const Dimension& dim) {
    std::map<std::string, VolumeSplitter::Part> byValue;
    for (const auto& m : part.members) {
        const auto [key, words] = dim.keyAndWords(frameOf(instances, m).dimensions);
        auto& sub = byValue[key];
        if (sub.members.empty())
            sub.varying = part.varying.empty() ? words : (words.empty() ? part.varying : part.varying + ", " + words);
        sub.members.push_back(m);
    }
    std::vector<VolumeSplitter::Part> out;
    for (auto& [key, sub] : byValue) out.push_back(std::move(sub));
    return out;
}

}  // namespace

VolumeSplitter::Result VolumeSplitter::split(const std::vector<DicomInstance>& instances,
                                             const std::vector<Member>& members, const glm::dvec3& normal) {
    // Positions closer than a twentieth of the stack's mean spacing (1 µm at least) are one
    // position: two acquisitions 2 µm apart had been stacked as one, resampled to 9000 slices.
    const auto along = positionsAlong(instances, members, normal);
    const double tolerance =
        along.size() > 1 ? std::max(1e-3, 0.05 * (along.back() - along.front()) / double(along.size() - 1)) : 1e-3;
    const auto repeated = [&](const Part& p) { return repeatedPositions(instances, p.members, normal, tolerance); };
    Result r;
    // Without a position anywhere, nothing says which images share one: images of different
    // type, echo, diffusion or time point are never stacked together in file order.
    if (along.empty()) {
        for (std::size_t d = 0; d < 4 && d < dimensions().size(); ++d)
            if (auto parts = splitBy(instances, {members, ""}, dimensions()[d]); parts.size() > 1) {
                r.parts = std::move(parts);
                return r;
            }
        r.parts.push_back({members, ""});
        return r;
    }

    // Where images share positions, the first dimension (in dimensions()' order) that tells some
    // apart without leaving a fragment, a part covering less than half the positions: a trigger
    // time that differs on every image of two acquisitions tells them apart too, but into
    // one-image volumes, and one image of another ImageType per acquisition would become a
    // volume of its own. Its parts are split further where positions still repeat (DTI's two
    // b0 volumes by their acquisition). When every such dimension leaves fragments, the first
    // that tells some apart.
    std::vector<Part> work{{members, ""}};
    std::vector<Part> done;
    while (!work.empty()) {
        Part part = std::move(work.back());
        work.pop_back();
        const std::size_t before = repeated(part);
        if (before == 0) {
            done.push_back(std::move(part));
            continue;
        }
        const std::size_t positions = distinctPositions(instances, part.members, normal, tolerance);
        std::vector<Part> best, first;
        for (const auto& dim : dimensions()) {
            auto parts = splitBy(instances, part, dim);
            if (parts.size() < 2) continue;
            std::size_t after = 0;
            bool fragment = false;
            for (const auto& p : parts) {
                after += repeated(p);
                fragment = fragment || 2 * p.members.size() < positions;
            }
            if (after >= before) continue;
            if (!fragment) {
                best = std::move(parts);
                break;
            }
            if (first.empty()) first = std::move(parts);
        }
        if (best.empty()) best = std::move(first);
        if (!best.empty()) {
            for (auto it = best.rbegin(); it != best.rend(); ++it) work.push_back(std::move(*it));
        } else {
            r.refused.push_back(std::to_string(before) + " images" + (part.varying.empty() ? "" : " of " + part.varying) +
                                " share positions (within " + num(tolerance) +
                                " mm) and nothing tells them apart (image type, echo, diffusion, time point, trigger "
                                "time, acquisition, stack): that volume is refused rather than mixed");
        }
    }
    // Images at distinct positions, unevenly spaced, that one dimension divides into evenly
    // spaced parts of two images or more lying over each other (pre- and post-contrast 0.3 mm
    // apart): two acquisitions, never interleaved into one stack and interpolated between.
    // Parts one after another (a scan in two ranges) or of one image each (an acquisition
    // number per image) stay one stack.
    for (auto& part : done) {
        std::vector<Part> parts;
        if (!evenlySpaced(instances, part.members, normal)) {
            for (const auto& dim : dimensions()) {
                parts = splitBy(instances, part, dim);
                bool apart = parts.size() >= 2;
                std::vector<std::pair<double, double>> ranges;
                std::vector<double> spacings;
                for (const auto& p : parts) {
                    const auto a = positionsAlong(instances, p.members, normal);
                    apart = apart && a.size() >= 2 && evenlySpaced(instances, p.members, normal);
                    if (a.size() >= 2) spacings.push_back((a.back() - a.front()) / double(a.size() - 1));
                    if (!a.empty()) ranges.emplace_back(a.front(), a.back());
                }
                std::sort(ranges.begin(), ranges.end());
                bool overlap = false;
                for (std::size_t i = 1; i < ranges.size(); ++i) overlap = overlap || ranges[i].first < ranges[i - 1].second;
                // Not one grid interleaved (odd and even slices acquired apart, one slice lost):
                // its parts, merged, are evenly spaced at their spacing over their number; two
                // acquisitions offset a little come closer than half that.
                if (apart && overlap) {
                    std::sort(spacings.begin(), spacings.end());
                    const auto all = positionsAlong(instances, part.members, normal);
                    double closest = 1e300;
                    for (std::size_t i = 1; i < all.size(); ++i) closest = std::min(closest, all[i] - all[i - 1]);
                    apart = closest < 0.5 * spacings[spacings.size() / 2] / double(parts.size());
                }
                if (apart && overlap) break;
                parts.clear();
            }
        }
        if (parts.empty()) r.parts.push_back(std::move(part));
        else
            for (auto& p : parts) r.parts.push_back(std::move(p));
    }
    return r;
}

}  // namespace hvx::dicom
