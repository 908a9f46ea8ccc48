// Per-label volume and image statistics against a brute-force count over the dense arrays:
// the label map on its own (coarser, shifted) grid, the image a linear function of the patient
// point, so that each label's mean and SD are known from the voxel positions alone.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "core/base/JobContext.h"
#include "core/octree/OctreeBuilder.h"
#include "core/reference/LabelStatistics.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
double imageAt(const glm::dvec3& p) { return 3 * p.x + 2 * p.y - p.z + 100; }

void build(core::VoxelSource& s, const std::string& path, bool labels) {
    core::BuildOptions o;
    o.brickSize = 16;
    o.labels = labels;
    core::JobContext job;
    core::OctreeBuilder(o).build(s, path, job);
}
}  // namespace

TEST(LabelStatistics, VolumesAndMeansMatchABruteForceCount) {
    test::TempDir dir;
    core::VolumeGeometry ig;
    ig.scalarType = core::ScalarType::Float32;
    ig.spacing = {1.0, 1.0, 1.5};
    ig.origin = {-40, -40, -30};
    ig.modality = "CT";
    test::DenseVolume iv;
    iv.dims = {81, 81, 41};
    for (std::uint32_t k = 0; k < 41; ++k)
        for (std::uint32_t j = 0; j < 81; ++j)
            for (std::uint32_t i = 0; i < 81; ++i) iv.values.push_back(imageAt(ig.origin + glm::dvec3(i, j, k) * ig.spacing));
    test::MemoryVoxelSource image(ig, iv);
    build(image, dir.file("image.hvo"), false);

    core::VolumeGeometry lg;
    lg.scalarType = core::ScalarType::UInt8;
    lg.isLabel = true;
    lg.spacing = {2.0, 1.5, 3.0};
    lg.origin = {-37.3, -35.1, -27.8};
    test::DenseVolume lv;
    lv.dims = {40, 50, 24};
    std::map<int, std::vector<double>> want;  // label -> image values at its voxels inside the image
    std::map<int, std::uint64_t> count;
    for (std::uint32_t k = 0; k < 24; ++k)
        for (std::uint32_t j = 0; j < 50; ++j)
            for (std::uint32_t i = 0; i < 40; ++i) {
                const glm::dvec3 p = lg.origin + glm::dvec3(i, j, k) * lg.spacing;
                int l = 0;
                if (glm::length(p - glm::dvec3(5, -3, 2)) < 15) l = 1;
                else if (p.x > 25 && p.y > 20) l = 7;  // reaches past the image's +y and +z faces
                lv.values.push_back(l);
                if (l == 0) continue;
                ++count[l];
                const bool inside = p.x <= 40.5 && p.y <= 40.5 && p.z <= 30.75 && p.z >= -30.75;
                if (inside) want[l].push_back(imageAt(p));
            }
    test::MemoryVoxelSource labels(lg, lv);
    build(labels, dir.file("labels.hvo"), true);

    const auto ir = core::OctreeReader::open(dir.file("image.hvo"));
    const auto lr = core::OctreeReader::open(dir.file("labels.hvo"));
    core::JobContext job;
    const auto stats = core::LabelStatistics::compute(*ir, *lr, job);
    ASSERT_EQ(stats.rows.size(), 2u);
    EXPECT_EQ(stats.units, "HU");
    for (const auto& [label, values] : want) {
        const auto& r = stats.rows.at(label);
        EXPECT_EQ(r.voxels, count[label]) << label;
        EXPECT_NEAR(r.volumeMl, double(count[label]) * 2.0 * 1.5 * 3.0 / 1000.0, 1e-9) << label;
        EXPECT_EQ(r.sampled, values.size()) << label;
        double mean = 0;
        for (double v : values) mean += v;
        mean /= double(values.size());
        double var = 0;
        for (double v : values) var += (v - mean) * (v - mean);
        const double sd = std::sqrt(var / double(values.size()));
        // Trilinear of a linear function is exact; float storage rounds to ~1e-5.
        EXPECT_NEAR(r.mean, mean, 1e-3) << label;
        EXPECT_NEAR(r.sd, sd, 1e-3) << label;
        EXPECT_NEAR(r.min, *std::min_element(values.begin(), values.end()), 1e-3);
        EXPECT_NEAR(r.max, *std::max_element(values.begin(), values.end()), 1e-3);
    }
    EXPECT_LT(stats.rows.at(7).sampled, stats.rows.at(7).voxels);
    EXPECT_NE(stats.note.find("label(s) 7 reach outside the image"), std::string::npos) << stats.note;
    // An intensity volume is not a label map.
    EXPECT_THROW(core::LabelStatistics::compute(*ir, *ir, job), core::Error);
}

// A gantry-tilted (sheared) label grid: a voxel holds |det| of its axes, not the product of its
// spacings (it had been counted 1/cos(20°) too large); negative labels are counted like any
// other (a brick whose largest label was 0 or less had been skipped as background).
TEST(LabelStatistics, ShearedGridsAndNegativeLabelsAreCountedExactly) {
    test::TempDir dir;
    core::VolumeGeometry ig;
    ig.scalarType = core::ScalarType::Float32;
    ig.origin = {-20, -20, -20};
    test::DenseVolume iv;
    iv.dims = {40, 40, 40};
    iv.values.assign(40 * 40 * 40, 5.0);
    test::MemoryVoxelSource image(ig, iv);
    build(image, dir.file("image.hvo"), false);

    core::VolumeGeometry lg;
    lg.scalarType = core::ScalarType::Int16;
    lg.isLabel = true;
    lg.spacing = {1.0, 1.0, 1.5};
    lg.origin = {-10, -10, -10};
    const double tilt = 20.0 * 3.14159265358979323846 / 180.0;
    lg.direction[2] = glm::dvec3(0, std::sin(tilt), std::cos(tilt));
    test::DenseVolume lv;
    lv.dims = {20, 20, 10};
    std::map<int, std::uint64_t> count;
    for (std::uint32_t k = 0; k < 10; ++k)
        for (std::uint32_t j = 0; j < 20; ++j)
            for (std::uint32_t i = 0; i < 20; ++i) {
                const int l = i < 5 ? -1 : i < 12 ? 3 : 0;  // bricks of 16: the first holds only -1 and 3
                lv.values.push_back(l);
                if (l) ++count[l];
            }
    test::MemoryVoxelSource labels(lg, lv);
    build(labels, dir.file("labels.hvo"), true);
    const auto ir = core::OctreeReader::open(dir.file("image.hvo"));
    const auto lr = core::OctreeReader::open(dir.file("labels.hvo"));
    core::JobContext job;
    const auto stats = core::LabelStatistics::compute(*ir, *lr, job);
    ASSERT_EQ(stats.rows.size(), 2u);
    const double voxelMl = 1.0 * 1.0 * 1.5 * std::cos(tilt) / 1000.0;  // the parallelepiped, worked by hand
    for (const int l : {-1, 3}) {
        EXPECT_EQ(stats.rows.at(l).voxels, count[l]) << l;
        EXPECT_NEAR(stats.rows.at(l).volumeMl, double(count[l]) * voxelMl, 1e-12) << l;
        EXPECT_NEAR(stats.rows.at(l).mean, 5.0, 1e-6) << l;
    }
}

// An image built with --empty-below keeps bricks below the threshold without their values: a
// label lying in one has approximate figures and is named, per label (the note had named none
// and the CSV had not said which); a label elsewhere stays exact.
TEST(LabelStatistics, LabelsOverBricksStoredWithoutValuesAreMarkedApproximate) {
    test::TempDir dir;
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::Float32;
    g.modality = "CT";
    test::DenseVolume iv, lv;
    iv.dims = lv.dims = {48, 16, 16};
    for (std::uint32_t k = 0; k < 16; ++k)
        for (std::uint32_t j = 0; j < 16; ++j)
            for (std::uint32_t i = 0; i < 48; ++i) {
                // x < 32: air that varies (-1000 to -985), below the threshold (the first brick
                // with its border wholly); beyond, tissue.
                iv.values.push_back(i < 32 ? -1000.0 + double((i + j + k) % 16) : 40.0 + double(i));
                lv.values.push_back(i >= 4 && i < 12 ? 1 : (i >= 36 && i < 44 ? 2 : 0));
            }
    test::MemoryVoxelSource image(g, iv);
    core::BuildOptions o;
    o.brickSize = 16;
    o.emptyBelow = -500.0;
    core::JobContext job;
    core::OctreeBuilder(o).build(image, dir.file("image.hvo"), job);
    auto lg = g;
    lg.scalarType = core::ScalarType::UInt8;
    lg.isLabel = true;
    lg.modality = "OT";
    test::MemoryVoxelSource labels(lg, lv);
    build(labels, dir.file("labels.hvo"), true);
    const auto stats = core::LabelStatistics::compute(*core::OctreeReader::open(dir.file("image.hvo")),
                                                      *core::OctreeReader::open(dir.file("labels.hvo")), job);
    ASSERT_EQ(stats.rows.size(), 2u);
    EXPECT_FALSE(stats.rows.at(1).exact);
    EXPECT_TRUE(stats.rows.at(2).exact);
    EXPECT_NEAR(stats.rows.at(2).mean, 40.0 + 39.5, 1e-3);
    EXPECT_NE(stats.note.find("label(s) 1 lie where the image stores bricks without their values"), std::string::npos)
        << stats.note;
    const std::string csv = stats.csv(nullptr);
    EXPECT_NE(csv.find(",units,exact\n"), std::string::npos) << csv;
    EXPECT_NE(csv.find(",HU,no\n"), std::string::npos) << csv;
    EXPECT_NE(csv.find(",HU,yes\n"), std::string::npos) << csv;
}
