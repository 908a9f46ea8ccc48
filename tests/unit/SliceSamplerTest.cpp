// Slices through the octree: exact values and patient orientation on a volume whose stored
// axes run opposite to LPS (an RAS-ordered NIfTI-like grid), at full and reduced levels.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <memory>

#include <glm/mat4x4.hpp>

#include "core/octree/OctreeBuilder.h"
#include "core/reference/SliceSampler.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
// value = i + 100 j + 10000 k (linear, so trilinear sampling is exact)
struct Grid {
    test::TempDir dir;
    core::VolumeGeometry g;
    std::unique_ptr<core::OctreeReader> reader;
    Grid() {
        g.scalarType = core::ScalarType::Float32;
        g.spacing = {0.8, 0.9, 2.5};
        g.origin = {40.0, 30.0, -60.0};
        g.direction = glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1));  // i: right, j: anterior
        test::DenseVolume v;
        v.dims = {50, 40, 30};
        v.values.resize(50 * 40 * 30);
        for (std::size_t k = 0; k < 30; ++k)
            for (std::size_t j = 0; j < 40; ++j)
                for (std::size_t i = 0; i < 50; ++i) v.values[(k * 40 + j) * 50 + i] = double(i + 100 * j + 10000 * k);
        test::MemoryVoxelSource source(g, v);
        core::BuildOptions o;
        o.brickSize = 16;
        core::JobContext job;
        core::OctreeBuilder(o).build(source, dir.file("g.hvo"), job);
        reader = core::OctreeReader::open(dir.file("g.hvo"));
        g = reader->geometry();
    }
    double expected(const glm::dvec3& patient) const {
        const glm::dvec3 idx(glm::inverse(g.indexToPatient()) * glm::dvec4(patient, 1.0));
        return idx.x + 100 * idx.y + 10000 * idx.z;
    }
};
/// A float32 volume of `dims` built into an octree of 16³ (or `brick`) bricks, opened.
std::unique_ptr<core::OctreeReader> octreeOf(const test::TempDir& dir, core::VolumeGeometry g, std::array<std::uint32_t, 3> dims,
                                             const std::function<double(std::size_t i, std::size_t k)>& value,
                                             std::uint32_t brick = 16) {
    g.scalarType = core::ScalarType::Float32;
    test::DenseVolume v;
    v.dims = dims;
    const std::size_t slice = std::size_t(dims[0]) * dims[1];
    for (std::size_t k = 0; k < dims[2]; ++k)
        for (std::size_t i = 0; i < slice; ++i) v.values.push_back(value(i, k));
    test::MemoryVoxelSource source(g, v);
    core::BuildOptions o;
    o.brickSize = brick;
    core::JobContext job;
    core::OctreeBuilder(o).build(source, dir.file("v.hvo"), job);
    return core::OctreeReader::open(dir.file("v.hvo"));
}

}  // namespace

TEST(SliceSampler, FullResolutionSlicesGiveExactValuesInEveryStandardPlane) {
    Grid grid;
    core::BrickCache cache(64u << 20);
    const core::SliceSampler sampler(*grid.reader, cache);
    const glm::dvec3 centre(grid.g.indexToPatient() * glm::dvec4(24.3, 19.6, 14.2, 1.0));
    for (auto o : {core::SlicePlane::Orientation::Axial, core::SlicePlane::Orientation::Coronal,
                   core::SlicePlane::Orientation::Sagittal}) {
        const auto plane = core::SlicePlane::standard(o, centre, 0.7, 40, 30);
        const auto img = sampler.sample(plane);
        EXPECT_EQ(img.level, 0);
        int checked = 0;
        for (int j = 0; j < plane.height; ++j)
            for (int i = 0; i < plane.width; ++i) {
                const glm::dvec3 p = plane.centre + (i + 0.5 - plane.width / 2.0) * plane.pixelMm * plane.right +
                                     (j + 0.5 - plane.height / 2.0) * plane.pixelMm * plane.down;
                const float v = img.values[std::size_t(j * plane.width + i)];
                if (std::isnan(v)) continue;
                ASSERT_NEAR(v, grid.expected(p), 0.05) << "plane " << int(o) << " pixel " << i << "," << j;
                ++checked;
            }
        EXPECT_GT(checked, 40 * 30 / 2) << "most of the plane lies inside the volume";
    }
}

TEST(SliceSampler, AxialImagesShowThePatientsLeftOnTheRightAndAnteriorAtTheTop) {
    Grid grid;
    core::BrickCache cache(64u << 20);
    const core::SliceSampler sampler(*grid.reader, cache);
    const glm::dvec3 centre(grid.g.indexToPatient() * glm::dvec4(24.5, 19.5, 15, 1.0));
    const auto axial = sampler.sample(core::SlicePlane::standard(core::SlicePlane::Orientation::Axial, centre, 0.8, 20, 20));
    // Index i grows towards the patient's right (direction -x): the image's right has smaller i.
    const float left = axial.values[10 * 20 + 2], right = axial.values[10 * 20 + 17];
    EXPECT_GT(left, right) << "the image's left is the patient's right (larger i)";
    // Index j grows anteriorly (direction -y): the top of an axial image is anterior, larger j.
    EXPECT_GT(axial.values[2 * 20 + 10], axial.values[17 * 20 + 10]);
    const auto labels = core::SlicePlane::edgeLabels(core::SlicePlane::Orientation::Axial);
    EXPECT_STREQ(labels[0], "R");
    EXPECT_STREQ(labels[1], "L");
    EXPECT_STREQ(labels[2], "A");
}

TEST(SliceSampler, CoarsePixelsReadACoarseLevelThatAveragesTheSameValues) {
    Grid grid;
    core::BrickCache cache(64u << 20);
    const core::SliceSampler sampler(*grid.reader, cache);
    // Slices 2.5 mm apart: a level-1 voxel is 5 mm deep, so only pixels of 5 mm read it.
    EXPECT_EQ(sampler.levelFor(0.8), 0);
    EXPECT_EQ(sampler.levelFor(4.9), 0);
    EXPECT_EQ(sampler.levelFor(5.0), 1);
    EXPECT_EQ(sampler.levelFor(1000.0), grid.reader->levelCount() - 1);
    const glm::dvec3 centre(grid.g.indexToPatient() * glm::dvec4(24, 20, 15, 1.0));
    const auto img = sampler.sample(core::SlicePlane::standard(core::SlicePlane::Orientation::Coronal, centre, 5.0, 16, 16));
    EXPECT_EQ(img.level, 1);
    // Averaging a linear function keeps it linear: level 1 still matches to within a voxel's step.
    const float v = img.values[8 * 16 + 8];
    const glm::dvec3 p = centre + 0.5 * 5.0 * glm::dvec3(1, 0, 0) + 0.5 * 5.0 * glm::dvec3(0, 0, -1);
    EXPECT_NEAR(v, grid.expected(p), 0.5) << "level 1 of a linear function is the same function";
}

// An anisotropic volume (0.5 mm pixels, 3 mm slices, layers alternately 200 and 0): a thin
// axial slice at 1 mm pixels reads level 0, one acquired layer, where choosing the level by the
// pixel spacing alone had read level 1 and shown the mean of two layers (100).
TEST(SliceSampler, AThinSliceOfThickSlicesNeverAveragesTwoOfThem) {
    test::TempDir dir;
    core::VolumeGeometry g;
    g.spacing = {0.5, 0.5, 3.0};
    const auto reader = octreeOf(dir, g, {128, 128, 16}, [](std::size_t, std::size_t k) { return k % 2 ? 0.0 : 200.0; });
    core::BrickCache cache(64u << 20);
    const core::SliceSampler sampler(*reader, cache);
    const glm::dvec3 layer4(g.indexToPatient() * glm::dvec4(64, 64, 4, 1.0));
    for (const double pixel : {0.5, 1.0, 2.0}) {
        const auto img = sampler.sample(core::SlicePlane::standard(core::SlicePlane::Orientation::Axial, layer4, pixel, 32, 32));
        EXPECT_EQ(img.level, 0) << pixel << " mm pixels";
        EXPECT_EQ(img.values[16 * 32 + 16], 200.0f) << pixel << " mm pixels";
    }
}

#include "core/reference/VolumeHistogram.h"

TEST(VolumeHistogram, CountsEveryVoxelOfTheChosenLevelOnce) {
    Grid grid;  // values i + 100 j + 10000 k over 50 x 40 x 30 voxels
    const auto full = core::VolumeHistogram::compute(*grid.reader, 30, 1000000);
    EXPECT_EQ(full.level, 0);
    std::uint64_t total = 0;
    for (auto c : full.counts) total += c;
    EXPECT_EQ(total, 50u * 40u * 30u);
    // 30 bins over [0, 293949]: bin b holds the slices k with 10000 k in it; one slice per bin.
    for (auto c : full.counts) EXPECT_GT(c, 0u);
    const auto coarse = core::VolumeHistogram::compute(*grid.reader, 30, 4);
    EXPECT_GT(coarse.level, 0);
    total = 0;
    for (auto c : coarse.counts) total += c;
    EXPECT_EQ(total, 25u * 20u * 15u) << "level 1 has half the voxels per axis";
}

#include "core/volume/SubsampledVoxelSource.h"

TEST(SubsampledVoxelSource, KeepsEveryFactorthVoxelInPlace) {
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::Int16;
    g.spacing = {0.5, 0.6, 2.0};
    g.origin = {10, 20, 30};
    test::DenseVolume v;
    v.dims = {9, 8, 7};
    v.values.resize(9 * 8 * 7);
    for (std::size_t i = 0; i < v.values.size(); ++i) v.values[i] = double(i % 1000);
    core::SubsampledVoxelSource sub(std::make_unique<test::MemoryVoxelSource>(g, v), 4);
    const auto& s = sub.geometry();
    EXPECT_EQ(s.dims, (std::array<std::uint32_t, 3>{3, 2, 2}));
    EXPECT_EQ(s.spacing, glm::dvec3(2.0, 2.4, 8.0));
    EXPECT_EQ(s.origin, g.origin) << "voxel 0 stays where it was";
    std::vector<std::int16_t> out(3 * 2 * 2);
    sub.readSlices(0, 2, out.data());
    for (std::size_t k = 0; k < 2; ++k)
        for (std::size_t j = 0; j < 2; ++j)
            for (std::size_t i = 0; i < 3; ++i)
                EXPECT_EQ(out[(k * 2 + j) * 3 + i], std::int16_t(((k * 4 * 8 + j * 4) * 9 + i * 4) % 1000));
}

// At a coarser level a 37-voxel axis has 19 voxels, the last reaching past the volume: nothing
// is drawn there (it had been, up to 2^level - 1 voxels beyond the volume's edge).
TEST(SliceSampler, CoarseLevelsStopAtTheVolumesEdge) {
    test::TempDir dir;
    const auto reader = octreeOf(dir, {}, {37, 37, 37}, [](std::size_t, std::size_t) { return 100.0; }, 8);
    core::BrickCache cache(64u << 20);
    const core::SliceSampler sampler(*reader, cache);
    ASSERT_GE(reader->levelCount(), 3);
    for (int level = 0; level < 3; ++level) {
        EXPECT_FLOAT_EQ(float(sampler.valueAt({36.4, 18, 18}, level)), 100.0f) << "inside, level " << level;
        EXPECT_TRUE(std::isnan(sampler.valueAt({36.6, 18, 18}, level))) << "past the edge (36.5 mm), level " << level;
        EXPECT_TRUE(std::isnan(sampler.valueAt({18, 18, 37.5}, level))) << "level " << level;
    }
}

// An overlay laid over a slab is the overlay's own slab (its MIP over a MIP: a hot spot beside
// the plane shows, as in the base), a thin slice over a thin one; a label map stays thin.
TEST(SliceSampler, AnOverlayOverASlabIsItsOwnSlab) {
    Grid grid;  // values i + 100 j + 10000 k: a MIP along k is the slab's top layer
    core::BrickCache cache(64u << 20);
    const core::SliceSampler sampler(*grid.reader, cache);
    const glm::dvec3 centre(grid.g.indexToPatient() * glm::dvec4(24, 20, 15, 1.0));
    const auto plane = core::SlicePlane::standard(core::SlicePlane::Orientation::Axial, centre, 0.8, 16, 16);
    const auto slab = sampler.sampleSlab(plane, 10.0, core::SlabMode::Mip);
    EXPECT_EQ(slab.slabMode, core::SlabMode::Mip);
    const auto like = sampler.sampleLike(plane, slab);
    EXPECT_EQ(like.values, slab.values);
    EXPECT_EQ(like.slabMm, 10.0);
    const auto thin = sampler.sample(plane);
    EXPECT_EQ(sampler.sampleLike(plane, thin).values, thin.values);
    EXPECT_GT(like.values[8 * 16 + 8], thin.values[8 * 16 + 8] + 10000.0) << "the MIP reaches layers above the plane";
    const auto mean = sampler.sampleSlab(plane, 10.0, core::SlabMode::Mean);
    EXPECT_EQ(sampler.sampleLike(plane, mean).values, mean.values);
}
