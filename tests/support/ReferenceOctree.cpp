#include "tests/support/ReferenceOctree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace hvx::test {

double DenseVolume::clamped(long i, long j, long k) const {
    i = std::clamp<long>(i, 0, long(dims[0]) - 1);
    j = std::clamp<long>(j, 0, long(dims[1]) - 1);
    k = std::clamp<long>(k, 0, long(dims[2]) - 1);
    return values[(std::size_t(k) * dims[1] + std::size_t(j)) * dims[0] + std::size_t(i)];
}

std::vector<DenseVolume> referencePyramid(const DenseVolume& level0, int levels, core::ScalarType type, bool labels) {
    std::vector<DenseVolume> pyr{level0};
    for (int l = 1; l < levels; ++l) {
        const DenseVolume& s = pyr.back();
        DenseVolume d;
        for (int a = 0; a < 3; ++a) d.dims[std::size_t(a)] = (s.dims[std::size_t(a)] + 1) / 2;
        d.values.resize(std::size_t(d.dims[0]) * d.dims[1] * d.dims[2]);
        for (std::uint32_t z = 0; z < d.dims[2]; ++z)
            for (std::uint32_t y = 0; y < d.dims[1]; ++y)
                for (std::uint32_t x = 0; x < d.dims[0]; ++x) {
                    std::vector<double> cell;
                    for (std::uint32_t zz = 2 * z; zz < std::min(s.dims[2], 2 * z + 2); ++zz)
                        for (std::uint32_t yy = 2 * y; yy < std::min(s.dims[1], 2 * y + 2); ++yy)
                            for (std::uint32_t xx = 2 * x; xx < std::min(s.dims[0], 2 * x + 2); ++xx)
                                cell.push_back(s.values[(std::size_t(zz) * s.dims[1] + yy) * s.dims[0] + xx]);
                    double v;
                    if (labels) {
                        std::map<double, int> counts;
                        for (double c : cell) ++counts[c];
                        int best = 0;
                        v = 0;
                        for (const auto& [value, count] : counts)  // ascending: ties keep the smallest
                            if (count > best) {
                                best = count;
                                v = value;
                            }
                    } else {
                        double sum = 0;
                        for (double c : cell) sum += c;
                        v = sum / double(cell.size());
                        v = type == core::ScalarType::Float32 ? double(float(v)) : double(std::llround(v));
                    }
                    d.values[(std::size_t(z) * d.dims[1] + y) * d.dims[0] + x] = v;
                }
        pyr.push_back(std::move(d));
    }
    return pyr;
}

void expectOctreeMatches(const core::OctreeReader& reader, const std::vector<DenseVolume>& pyramid) {
    ASSERT_EQ(std::size_t(reader.levelCount()), pyramid.size());
    const long b = long(reader.brickSize()), border = long(reader.border()), e = long(reader.brickEdge());
    std::size_t mismatches = 0;
    for (std::uint32_t id = 0; id < reader.nodes().size(); ++id) {
        const auto& n = reader.nodes()[id];
        const auto brick = reader.readBrick(id);
        const DenseVolume& lv = pyramid[n.level];
        for (long z = 0; z < e; ++z)
            for (long y = 0; y < e; ++y)
                for (long x = 0; x < e; ++x) {
                    const double want = lv.clamped(long(n.x) * b - border + x, long(n.y) * b - border + y,
                                                   long(n.z) * b - border + z);
                    const double got = brick.value(std::uint32_t(x), std::uint32_t(y), std::uint32_t(z));
                    if (!brick.empty && got != want && ++mismatches <= 5)
                        ADD_FAILURE() << "node " << id << " level " << int(n.level) << " sample (" << x << "," << y
                                      << "," << z << "): got " << got << " want " << want;
                    if (want < n.minValue || want > n.maxValue) {
                        if (++mismatches <= 5)
                            ADD_FAILURE() << "node " << id << " range [" << n.minValue << "," << n.maxValue
                                          << "] misses " << want;
                    }
                }
        if (n.parent != core::hvo::kNoNode) {
            const auto& p = reader.nodes()[n.parent];
            EXPECT_LE(p.minValue, n.minValue);
            EXPECT_GE(p.maxValue, n.maxValue);
        }
    }
    EXPECT_EQ(mismatches, 0u);
}

}  // namespace hvx::test
