// What a volume opens with in the slice views (core::DisplayWindow), the presets it offers, the
// histogram's percentiles, and the DICOM windows carried through the .hvo.
#include <gtest/gtest.h>

#include "core/base/JobContext.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/reference/VolumeHistogram.h"
#include "core/volume/DisplayWindow.h"
#include "core/volume/PhantomVoxelSource.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/TempDir.h"

using namespace hvx;

TEST(DisplayWindow, DicomFirstThenCtDefaultThenPercentilesThenRange) {
    core::VolumeGeometry g;
    g.modality = "MR";
    g.valueMin = 0;
    g.valueMax = 1000;
    g.rescaleSlope = 2;
    g.rescaleIntercept = -100;
    auto w = core::DisplayWindow::initial(g);
    EXPECT_DOUBLE_EQ(w.centre, 900);  // (-100 + 1900) / 2
    EXPECT_DOUBLE_EQ(w.width, 2000);
    w = core::DisplayWindow::initial(g, std::make_pair(100.0, 300.0));
    EXPECT_DOUBLE_EQ(w.centre, 200);
    EXPECT_DOUBLE_EQ(w.width, 200);
    g.modality = "CT";
    w = core::DisplayWindow::initial(g, std::make_pair(100.0, 300.0));
    EXPECT_DOUBLE_EQ(w.centre, 40);
    EXPECT_DOUBLE_EQ(w.width, 400);
    g.windows = {{"SOFT", 50, 350}, {"BONE", 300, 1500}};
    w = core::DisplayWindow::initial(g);
    EXPECT_EQ(w.name, "SOFT");
    const auto presets = core::DisplayWindow::presetsFor(g);
    ASSERT_EQ(presets.size(), 2u + 8u);
    EXPECT_EQ(presets[1].name, "BONE");
    EXPECT_EQ(presets[2].name, "brain");
    EXPECT_EQ(presets[6].name, "lung");
    EXPECT_DOUBLE_EQ(presets[6].centre, -600);
    g.modality = "MR";
    EXPECT_EQ(core::DisplayWindow::presetsFor(g).size(), 2u) << "CT presets only for CT";
}

TEST(DisplayWindow, HistogramPercentiles) {
    core::VolumeHistogram h;
    h.valueMin = 0;
    h.valueMax = 100;
    h.counts.assign(100, 0);
    for (int b = 0; b < 100; ++b) h.counts[std::size_t(b)] = 10;  // uniform: the percentile is p * 100
    EXPECT_NEAR(h.percentile(0.01), 1.0, 1e-9);
    EXPECT_NEAR(h.percentile(0.99), 99.0, 1e-9);
    EXPECT_NEAR(h.percentile(0.5), 50.0, 1e-9);
    h.counts.assign(100, 0);
    h.counts[20] = 1000;  // everything in one bin
    EXPECT_GE(h.percentile(0.01), 20.0);
    EXPECT_LE(h.percentile(0.99), 21.0);
}

TEST(DisplayWindow, WindowsTravelThroughTheOctreeAndOldFilesHaveNone) {
    test::TempDir dir;
    core::PhantomVoxelSource p({24, 24, 24}, 1);
    core::VolumeGeometry g = p.geometry();
    g.windows = {{"WINDOW ONE", 40, 400}, {"A NAME LONGER THAN FIFTEEN", -600, 1500}};
    test::DenseVolume v;
    v.dims = g.dims;
    v.values.assign(std::size_t(24 * 24 * 24), 0.0);
    test::MemoryVoxelSource src(g, v);
    core::JobContext job;
    core::OctreeBuilder(core::BuildOptions{}).build(src, dir.file("w.hvo"), job);
    const auto r = core::OctreeReader::open(dir.file("w.hvo"));
    ASSERT_EQ(r->geometry().windows.size(), 2u);
    EXPECT_EQ(r->geometry().windows[0].name, "WINDOW ONE");
    EXPECT_DOUBLE_EQ(r->geometry().windows[1].centre, -600);
    EXPECT_EQ(r->geometry().windows[1].name, "A NAME LONGER T");  // 15 characters kept
    core::OctreeBuilder(core::BuildOptions{}).build(p, dir.file("none.hvo"), job);
    EXPECT_TRUE(core::OctreeReader::open(dir.file("none.hvo"))->geometry().windows.empty());
}
