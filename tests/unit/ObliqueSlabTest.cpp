// Oblique planes and thick slabs through the octree against a direct computation on the dense
// volume: an oblique plane equals trilinear resampling of the dense values at each pixel's
// patient position; a slab's MIP, MinIP and mean equal the maximum, minimum and mean over the
// dense voxels it spans; tilted planes keep the view a reader expects, with the right letters.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <glm/matrix.hpp>

#include "core/base/Error.h"
#include "core/base/JobContext.h"
#include "core/octree/OctreeBuilder.h"
#include "core/reference/SliceSampler.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
struct Volume {
    test::TempDir dir;
    core::VolumeGeometry g;
    test::DenseVolume v;
    std::unique_ptr<core::OctreeReader> reader;
    Volume(glm::dvec3 spacing, glm::dmat3 direction, unsigned seed) {
        g.scalarType = core::ScalarType::Float32;
        g.spacing = spacing;
        g.origin = {31.0, -17.5, 80.0};
        g.direction = direction;
        v = test::randomVolume({37, 33, 29}, core::ScalarType::Float32, seed);
        g.dims = v.dims;
        test::MemoryVoxelSource source(g, v);
        core::BuildOptions o;
        o.brickSize = 16;
        core::JobContext job;
        core::OctreeBuilder(o).build(source, dir.file("v.hvo"), job);
        reader = core::OctreeReader::open(dir.file("v.hvo"));
    }
    double at(long i, long j, long k) const { return v.clamped(i, j, k); }
    /// Trilinear interpolation of the dense values at a patient point; NaN outside the volume.
    double trilinear(const glm::dvec3& patient) const {
        const glm::dvec3 c(glm::inverse(g.indexToPatient()) * glm::dvec4(patient, 1.0));
        for (int a = 0; a < 3; ++a)
            if (c[a] < 0 || c[a] > double(g.dims[std::size_t(a)] - 1)) return std::nan("");
        const glm::dvec3 f0 = glm::floor(c);
        const glm::dvec3 f = c - f0;
        double s = 0;
        for (int n = 0; n < 8; ++n) {
            const int dx = n & 1, dy = (n >> 1) & 1, dz = (n >> 2) & 1;
            s += (dx ? f.x : 1 - f.x) * (dy ? f.y : 1 - f.y) * (dz ? f.z : 1 - f.z) *
                 at(long(f0.x) + dx, long(f0.y) + dy, long(f0.z) + dz);
        }
        return s;
    }
};

glm::dvec3 pixelCentre(const core::SlicePlane& p, int i, int j) {
    return p.centre + (i + 0.5 - p.width / 2.0) * p.pixelMm * p.right + (j + 0.5 - p.height / 2.0) * p.pixelMm * p.down;
}
}  // namespace

TEST(ObliqueSlice, EqualsTrilinearResamplingOfTheDenseVolume) {
    const glm::dmat3 ras(glm::dvec3(-1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1));  // stored R to L, A to P
    Volume vol({0.8, 0.9, 1.5}, ras, 11);
    core::BrickCache cache(64u << 20);
    const core::SliceSampler sampler(*vol.reader, cache);
    const glm::dvec3 centre(vol.g.indexToPatient() * glm::dvec4(18.2, 15.7, 13.4, 1.0));
    for (const glm::dvec3 normal : {glm::dvec3(0.3, -0.5, 0.8), glm::dvec3(0.9, 0.2, -0.3), glm::dvec3(0.1, 1.0, 0.2)}) {
        const auto plane = core::SlicePlane::oblique(normal, centre, 0.6, 41, 37);
        EXPECT_NEAR(std::abs(glm::dot(plane.normal(), glm::normalize(normal))), 1.0, 1e-12);
        EXPECT_NEAR(glm::dot(plane.right, plane.down), 0.0, 1e-12) << "the plane's axes stay perpendicular";
        const auto img = sampler.sample(plane, 0);
        int compared = 0;
        double worst = 0;
        for (int j = 0; j < plane.height; ++j)
            for (int i = 0; i < plane.width; ++i) {
                const double want = vol.trilinear(pixelCentre(plane, i, j));
                const float got = img.values[std::size_t(j) * std::size_t(plane.width) + std::size_t(i)];
                if (std::isnan(want)) continue;
                ASSERT_FALSE(std::isnan(got)) << i << "," << j;
                worst = std::max(worst, std::abs(double(got) - want));
                ++compared;
            }
        EXPECT_GT(compared, 600) << "most of the plane lies in the volume";
        EXPECT_LT(worst, 0.01) << "float storage and interpolation in float: the values agree to 1e-2 of a 4000 range";
    }
}

TEST(ObliqueSlice, TiltedPlanesKeepTheReadersViewAndLetters) {
    const glm::dvec3 c(0.0);
    const auto axial = core::SlicePlane::standard(core::SlicePlane::Orientation::Axial, c, 1, 8, 8);
    EXPECT_EQ(axial.edgeLabels(), (std::array<std::string, 4>{"R", "L", "A", "P"}));
    // 10 degrees off axial, towards anterior: still an axial seen from the feet.
    const double t = 10.0 * M_PI / 180.0;
    const auto slight = core::SlicePlane::oblique({0, -std::sin(t), std::cos(t)}, c, 1, 8, 8);
    EXPECT_EQ(slight.edgeLabels(), (std::array<std::string, 4>{"R", "L", "A", "P"}));
    EXPECT_NEAR(glm::dot(slight.right, glm::dvec3(1, 0, 0)), 1.0, 1e-12) << "tilting about left-right keeps the rows";
    // 40 degrees: the plane's top edge now also points inferior, its bottom superior (the normal
    // leans anterior-superior, so the plane's anterior part dips towards the feet).
    const double u = 40.0 * M_PI / 180.0;
    const auto steep = core::SlicePlane::oblique({0, -std::sin(u), std::cos(u)}, c, 1, 8, 8);
    EXPECT_EQ(steep.edgeLabels(), (std::array<std::string, 4>{"R", "L", "AI", "PS"}));
    // A normal pointing the other way is the same plane, seen the same way.
    const auto flipped = core::SlicePlane::oblique({0, std::sin(u), -std::cos(u)}, c, 1, 8, 8);
    EXPECT_EQ(flipped.edgeLabels(), steep.edgeLabels());
    // Near sagittal: seen from the patient's left, anterior on the left.
    const auto sag = core::SlicePlane::oblique({-1, 0.1, 0}, c, 1, 8, 8);
    EXPECT_EQ(sag.edgeLabels(), (std::array<std::string, 4>{"A", "P", "S", "I"}));
    EXPECT_THROW(core::SlicePlane::oblique({0, 0, 0}, c, 1, 8, 8), core::Error);
}

TEST(ThickSlab, MipMinIpAndMeanEqualTheDenseSlab) {
    Volume vol({1.0, 1.0, 1.0}, glm::dmat3(1.0), 12);
    core::BrickCache cache(64u << 20);
    const core::SliceSampler sampler(*vol.reader, cache);
    // An axial plane through voxel centres (odd size, 1 mm pixels): pixel (i, j) is voxel
    // (5 + i, 4 + j); a 4 mm slab spans layers k - 2 .. k + 2.
    const long k = 14;
    const glm::dvec3 centre(vol.g.indexToPatient() * glm::dvec4(5 + 12, 4 + 10, double(k), 1.0));
    const auto plane = core::SlicePlane::standard(core::SlicePlane::Orientation::Axial, centre, 1.0, 25, 21);
    for (const auto mode : {core::SlabMode::Mip, core::SlabMode::MinIp, core::SlabMode::Mean}) {
        const auto img = sampler.sampleSlab(plane, 4.0, mode, 0);
        EXPECT_EQ(img.slabSamples, 5);
        EXPECT_DOUBLE_EQ(img.slabMm, 4.0);
        for (int j = 0; j < plane.height; ++j)
            for (int i = 0; i < plane.width; ++i) {
                std::vector<double> column;
                for (long z = k - 2; z <= k + 2; ++z) column.push_back(vol.at(5 + i, 4 + j, z));
                const double want = mode == core::SlabMode::Mip     ? *std::max_element(column.begin(), column.end())
                                    : mode == core::SlabMode::MinIp ? *std::min_element(column.begin(), column.end())
                                                                    : (column[0] + column[1] + column[2] + column[3] + column[4]) / 5;
                ASSERT_NEAR(img.values[std::size_t(j) * 25 + std::size_t(i)], want, 2e-3 * std::max(1.0, std::abs(want)))
                    << "mode " << int(mode) << " pixel " << i << "," << j;
            }
    }
    // A slab thicker than the volume takes all of it; no thickness is refused.
    const auto all = sampler.sampleSlab(plane, 1e6, core::SlabMode::Mip, 0);
    EXPECT_LT(all.slabMm, 100.0);
    EXPECT_GT(all.slabMm, 29.0);
    EXPECT_THROW(sampler.sampleSlab(plane, 0.0, core::SlabMode::Mip), core::Error);
    EXPECT_THROW(sampler.sampleSlab(plane, std::nan(""), core::SlabMode::Mip), core::Error);
}
