#include "core/octree/SplitVoxelFitter.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "core/base/Error.h"

namespace hvx::core {

void SplitVoxelOptions::validate() const {
    if (n < 2 || n > 8)
        throw Error("--split-n " + std::to_string(n) + " is out of range: a split-voxel stands for 2 to 8 voxels per edge");
    if (overlap > 4)
        throw Error("--split-overlap " + std::to_string(overlap) + " is out of range: 0 to 4 neighbour layers");
    if (threshold && (!std::isfinite(*threshold) || *threshold < 0.0))
        throw Error("--split-threshold must be a finite value of 0 or more (" + std::to_string(*threshold) + " given)");
}

SplitVoxelFitter::SplitVoxelFitter(SplitVoxelOptions options) : options_(options) { options_.validate(); }

namespace {

/// A sample's position in cell coordinates.
glm::vec3 position(std::uint32_t i, std::uint32_t j, std::uint32_t k, std::uint32_t S, std::uint32_t M) {
    return (glm::vec3(float(i), float(j), float(k)) - float(M) + 0.5f) / float(S);
}

/// The lower median of a set of values: always one of them, never a blend.
float lowerMedian(std::vector<float>& v) {
    auto mid = v.begin() + std::ptrdiff_t((v.size() - 1) / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

/// The plane between the window's two classes (cls: 1 front, 2 back, 0 neither). Eqs. 4.1–4.2
/// first: the normal along the barycentres' difference, through the point that splits it in the
/// classes' proportion. Two refinements then make it exact for a plane through the window: the
/// normal becomes Fisher's discriminant direction (the difference corrected by the classes'
/// pooled spread, which the cube's corners skew), and the offset moves to the split along it
/// that misplaces fewest samples (the nearest such to Eq. 4.2's). Uniform when the classes are
/// not separable (barycentres within half a sample) or the plane misses the cell.
SplitVoxel fromClasses(float front, float back, const std::vector<std::uint8_t>& cls, std::uint32_t S, std::uint32_t M,
                       float uniformValue) {
    const std::uint32_t E = S + 2 * M;
    glm::dvec3 pf(0.0), pb(0.0);
    double nf = 0, nb = 0;
    for (std::uint32_t k = 0, at = 0; k < E; ++k)
        for (std::uint32_t j = 0; j < E; ++j)
            for (std::uint32_t i = 0; i < E; ++i, ++at) {
                if (cls[at] == 1) pf += glm::dvec3(position(i, j, k, S, M)), nf += 1;
                if (cls[at] == 2) pb += glm::dvec3(position(i, j, k, S, M)), nb += 1;
            }
    if (nf == 0 || nb == 0) return SplitVoxel::uniform(uniformValue);
    pf /= nf;
    pb /= nb;
    const glm::dvec3 d = pf - pb;
    const double len = glm::length(d);
    if (len < 0.5 / double(S)) return SplitVoxel::uniform(uniformValue);
    // Fisher: n ∝ Sw⁻¹ (pf − pb), Sw the pooled within-class scatter.
    glm::dmat3 sw(0.0);
    for (std::uint32_t k = 0, at = 0; k < E; ++k)
        for (std::uint32_t j = 0; j < E; ++j)
            for (std::uint32_t i = 0; i < E; ++i, ++at) {
                if (cls[at] == 0) continue;
                const glm::dvec3 r = glm::dvec3(position(i, j, k, S, M)) - (cls[at] == 1 ? pf : pb);
                sw += glm::outerProduct(r, r);
            }
    glm::dvec3 n = d / len;
    if (std::abs(glm::determinant(sw)) > 1e-9) {
        const glm::dvec3 fisher = glm::inverse(sw) * d;
        if (glm::length(fisher) > 0.0 && glm::dot(fisher, d) > 0.0) n = glm::normalize(fisher);
    }
    // Eq. 4.2's point, projected; then the split along n that misplaces fewest samples, found
    // over a histogram of the samples' projections (bins finer than the encoding's offset
    // quantum, so no sort is needed).
    const glm::dvec3 centre(0.5);
    const double eq42 = glm::dot(n, pb + d * (nb / (nf + nb)) - centre);
    constexpr int kBins = 1024;
    const double span = 0.5 * double(E) / double(S) * (std::abs(n.x) + std::abs(n.y) + std::abs(n.z)) + 1e-9;
    const std::uint32_t interiorWeight = (E * E * E) / (S * S * S);
    thread_local std::vector<std::int32_t> fronts, backs;
    fronts.assign(kBins, 0);
    backs.assign(kBins, 0);
    for (std::uint32_t k = 0, at = 0; k < E; ++k)
        for (std::uint32_t j = 0; j < E; ++j)
            for (std::uint32_t i = 0; i < E; ++i, ++at) {
                if (cls[at] == 0) continue;
                const double x = glm::dot(n, glm::dvec3(position(i, j, k, S, M)) - centre);
                const int bin = std::clamp(int((x + span) / (2.0 * span) * kBins), 0, kBins - 1);
                // The cell's own samples weigh as much as the whole window: the plane must
                // first be right inside the cell, the overlap only steers it.
                const bool own = i >= M && i < M + S && j >= M && j < M + S && k >= M && k < M + S;
                (cls[at] == 1 ? fronts : backs)[std::size_t(bin)] += own ? std::int32_t(interiorWeight) : 1;
            }
    // Split at the lower edge of bin b: bins below are behind, from b on in front.
    long misplaced = 0;  // b = 0: every back sample in front
    for (const auto c : backs) misplaced += c;
    long best = misplaced;
    double offset = eq42, bestGap = 1e300;
    for (int bin = 0; bin <= kBins; ++bin) {
        if (bin > 0) misplaced += fronts[std::size_t(bin - 1)] - backs[std::size_t(bin - 1)];
        const double at = -span + 2.0 * span * double(bin) / kBins;
        const double gap = std::abs(at - eq42);
        if (misplaced < best || (misplaced == best && gap < bestGap)) {
            best = misplaced;
            bestGap = gap;
            offset = at;
        }
    }
    const double reach = 0.5 * (std::abs(n.x) + std::abs(n.y) + std::abs(n.z));  // the cell's extent along n
    if (offset >= reach) return SplitVoxel::uniform(back);    // the whole cell behind the plane
    if (offset <= -reach) return SplitVoxel::uniform(front);  // the whole cell in front of it
    return {front, back, glm::vec3(n), float(offset)};
}

}  // namespace

SplitVoxel SplitVoxelFitter::fit(const float* w, std::uint32_t S, std::uint32_t M) const {
    const std::uint32_t E = S + 2 * M;
    const std::size_t count = std::size_t(E) * E * E;
    // The cell's own samples decide its two materials; the overlap only helps place the plane
    // between them. (Choosing them over the whole window, as the thesis does, lets a third
    // material of the overlap outvote a thin one inside the cell: a rib two voxels thick in
    // tissue next to air vanished from CT at every level.)
    thread_local std::vector<float> interior;
    interior.clear();
    for (std::uint32_t k = M; k < M + S; ++k)
        for (std::uint32_t j = M; j < M + S; ++j)
            for (std::uint32_t i = M; i < M + S; ++i) interior.push_back(w[(std::size_t(k) * E + j) * E + i]);
    thread_local std::vector<std::uint8_t> cls;
    cls.assign(count, 0);
    if (options_.labels) {
        thread_local std::vector<std::pair<float, std::uint32_t>> counts;
        counts.clear();
        for (const float v : interior) {
            auto it = std::find_if(counts.begin(), counts.end(), [v](const auto& c) { return c.first == v; });
            if (it == counts.end()) counts.emplace_back(v, 1u);
            else ++it->second;
        }
        std::sort(counts.begin(), counts.end(),
                  [](const auto& x, const auto& y) { return x.second > y.second || (x.second == y.second && x.first < y.first); });
        const float front = counts[0].first;
        if (counts.size() == 1) return SplitVoxel::uniform(front);
        const float back = counts[1].first;
        for (std::size_t a = 0; a < count; ++a) cls[a] = w[a] == front ? 1 : w[a] == back ? 2 : 0;
        return fromClasses(front, back, cls, S, M, front);
    }
    // Intensities: two-means clustering (Lloyd) of the cell's samples, seeded at their extremes.
    const auto [lo, hi] = std::minmax_element(interior.begin(), interior.end());
    double sum = 0.0;
    for (const float v : interior) sum += v;
    const float mean = float(sum / double(interior.size()));
    const double threshold = options_.threshold.value_or(0.0);
    if (*hi - *lo <= threshold || *hi == *lo) return SplitVoxel::uniform(mean);
    double m0 = *lo, m1 = *hi;
    thread_local std::vector<std::uint8_t> high;
    high.assign(interior.size(), 0);
    for (int iteration = 0; iteration < 64; ++iteration) {
        bool changed = false;
        double s0 = 0, s1 = 0;
        std::size_t n0 = 0, n1 = 0;
        for (std::size_t a = 0; a < interior.size(); ++a) {
            const std::uint8_t h = std::abs(interior[a] - m1) < std::abs(interior[a] - m0) ? 1 : 0;
            changed |= h != high[a];
            high[a] = h;
            (h ? s1 : s0) += interior[a];
            (h ? n1 : n0) += 1;
        }
        if (n0 == 0 || n1 == 0) break;
        m0 = s0 / double(n0);
        m1 = s1 / double(n1);
        if (!changed && iteration > 0) break;
    }
    if (std::abs(m1 - m0) < threshold) return SplitVoxel::uniform(mean);
    thread_local std::vector<float> frontValues, backValues;
    frontValues.clear();
    backValues.clear();
    for (std::size_t a = 0; a < interior.size(); ++a) (high[a] ? frontValues : backValues).push_back(interior[a]);
    if (frontValues.empty() || backValues.empty()) return SplitVoxel::uniform(mean);
    const bool frontLarger = frontValues.size() >= backValues.size();
    const float front = lowerMedian(frontValues), back = lowerMedian(backValues);
    // The window's samples by the nearer of the two means; a sample farther from both than
    // half their gap is a third material and places no plane.
    const double gap = std::abs(m1 - m0);
    for (std::size_t a = 0; a < count; ++a) {
        const double d0 = std::abs(w[a] - m0), d1 = std::abs(w[a] - m1);
        if (std::min(d0, d1) <= 0.5 * gap) cls[a] = d1 < d0 ? 1 : 2;
    }
    // Not separable: the cell is its larger cluster's material.
    return fromClasses(front, back, cls, S, M, frontLarger ? front : back);
}

}  // namespace hvx::core
