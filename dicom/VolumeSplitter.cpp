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
    return in.frameGeometry[std::min<std::size_t>(m.second, in.frameGeometry.size() - 1)];
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
             if (f.echoNumber) return std::make_pair(padded(*f.echoNumber), "echo " + std::to_string(*f.echoNumber) + te);
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

/// Frames at positions (along the normal, to 1 µm) held by more than one frame.
std::size_t repeatedPositions(const std::vector<DicomInstance>& instances, const std::vector<VolumeSplitter::Member>& m,
                              const glm::dvec3& normal) {
    std::map<long long, int> count;
    for (const auto& member : m) {
        const auto& fg = frameOf(instances, member);
        if (!fg.hasPosition) continue;
        ++count[std::llround(glm::dot(fg.position, normal) * 1000.0)];
    }
    std::size_t repeated = 0;
    for (const auto& [at, n] : count) repeated += std::size_t(n > 1 ? n : 0);
    return repeated;
}

}  // namespace

VolumeSplitter::Result VolumeSplitter::split(const std::vector<DicomInstance>& instances,
                                             const std::vector<Member>& members, const glm::dvec3& normal) {
    std::vector<Part> parts{{members, ""}};
    for (const auto& dim : dimensions()) {
        std::vector<Part> next;
        for (auto& part : parts) {
            if (repeatedPositions(instances, part.members, normal) == 0) {
                next.push_back(std::move(part));
                continue;
            }
            std::map<std::string, Part> byValue;  // sorted by key
            for (const auto& m : part.members) {
                const auto [key, words] = dim.keyAndWords(frameOf(instances, m).dimensions);
                auto& sub = byValue[key];
                if (sub.members.empty())
                    sub.varying = part.varying.empty() ? words : (words.empty() ? part.varying : part.varying + ", " + words);
                sub.members.push_back(m);
            }
            if (byValue.size() < 2) {
                next.push_back(std::move(part));
                continue;
            }
            for (auto& [key, sub] : byValue) next.push_back(std::move(sub));
        }
        parts = std::move(next);
    }
    Result r;
    for (auto& part : parts) {
        const std::size_t repeated = repeatedPositions(instances, part.members, normal);
        if (repeated == 0) {
            r.parts.push_back(std::move(part));
            continue;
        }
        r.refused.push_back(std::to_string(repeated) + " images" +
                            (part.varying.empty() ? "" : " of " + part.varying) +
                            " share positions and nothing tells them apart (image type, echo, diffusion, time point, "
                            "trigger time, acquisition, stack): that volume is refused rather than mixed");
    }
    return r;
}

}  // namespace hvx::dicom
