// Colour maps and label tables as the readers' own tools write them: mricron's binary .lut,
// ITK-SNAP label descriptions, FreeSurfer's LUT, 3D Slicer's colour tables; broken ones refused
// with the file and line named.
#include <gtest/gtest.h>

#include <fstream>

#include "core/appearance/ColorMap.h"
#include "core/appearance/LabelTable.h"
#include "core/base/Error.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
std::string write(const test::TempDir& dir, const std::string& name, const std::string& text) {
    std::ofstream(dir.file(name), std::ios::binary) << text;
    return dir.file(name);
}

std::string mricronLut(const test::TempDir& dir, std::size_t bytes) {
    std::string lut(bytes, '\0');
    for (std::size_t i = 0; i < std::min<std::size_t>(256, bytes); ++i) {
        lut[i] = char(i);                                // red rises
        if (256 + i < bytes) lut[256 + i] = char(255 - i);  // green falls
        if (512 + i < bytes) lut[512 + i] = char(i % 2 ? 200 : 0);
    }
    return write(dir, "map.lut", lut);
}

template <class F> std::string errorOf(F&& f) {
    try {
        f();
    } catch (const core::Error& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(ColourTables, BuiltInMapsRunFromTheirLowEndToTheirHighEnd) {
    const auto hot = core::ColorMap::named("hot");
    EXPECT_EQ(hot.at(0.0), (core::ColorMap::Rgb{0, 0, 0}));
    EXPECT_EQ(hot.at(1.0), (core::ColorMap::Rgb{255, 255, 255}));
    EXPECT_EQ(hot.at(1.0 / 3), (core::ColorMap::Rgb{255, 0, 0}));  // red first, then yellow
    EXPECT_EQ(core::ColorMap::named("GRAY").at(0.5), (core::ColorMap::Rgb{128, 128, 128}));
    EXPECT_EQ(core::ColorMap::named("rainbow").at(0.0)[2], 128);  // dark blue at the bottom
    EXPECT_EQ(core::ColorMap::named("pet").at(1.0), (core::ColorMap::Rgb{255, 255, 255}));
    for (const auto& n : core::ColorMap::builtinNames()) EXPECT_EQ(core::ColorMap::named(n).name(), n);
    const auto e = errorOf([] { core::ColorMap::named("viridian"); });
    EXPECT_NE(e.find("viridian"), std::string::npos);
    EXPECT_NE(e.find("hot, rainbow"), std::string::npos) << e;
}

TEST(ColourTables, MricronLutAndTextTablesLoadAsColourMaps) {
    test::TempDir dir;
    const auto lut = core::ColorMap::load(mricronLut(dir, 768));
    for (int i : {0, 1, 100, 255}) {
        EXPECT_EQ(lut.entries()[std::size_t(i)][0], i);
        EXPECT_EQ(lut.entries()[std::size_t(i)][1], 255 - i);
        EXPECT_EQ(lut.entries()[std::size_t(i)][2], i % 2 ? 200 : 0);
    }
    // A two-row Slicer table spreads from its first colour to its last.
    const auto ramp = core::ColorMap::load(write(dir, "ramp.ctbl", "# Color table file ramp\n0 lo 0 0 255 255\n9 hi 255 0 0 255\n"));
    EXPECT_EQ(ramp.at(0.0), (core::ColorMap::Rgb{0, 0, 255}));
    EXPECT_EQ(ramp.at(1.0), (core::ColorMap::Rgb{255, 0, 0}));
    EXPECT_EQ(ramp.entries()[51][0], 51);
    EXPECT_EQ(core::ColorMap::namedOrFile(dir.file("map.lut")).entries()[7][0], 7);
}

TEST(ColourTables, BrokenColourMapsAreRefusedWithTheFileAndLine) {
    test::TempDir dir;
    EXPECT_NE(errorOf([&] { core::ColorMap::load(mricronLut(dir, 700)); }).find("768 bytes (700 here)"), std::string::npos);
    EXPECT_NE(errorOf([&] { core::ColorMap::load(write(dir, "a.ctbl", "0 a 0 0 0 255\n1 b 300 0 0 255\n")); }).find("line 2"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { core::ColorMap::load(write(dir, "b.ctbl", "0 a 0 0 0 255\n0 b 1 1 1 255\n")); }).find("twice"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { core::ColorMap::load(write(dir, "c.ctbl", "# nothing\n")); }).find("at least two"), std::string::npos);
    EXPECT_NE(errorOf([&] { core::ColorMap::load(dir.file("absent.lut")); }).find("cannot open"), std::string::npos);
}

TEST(ColourTables, EachLabelFormatLoadsWithItsOwnOpacityConvention) {
    test::TempDir dir;
    // As ITK-SNAP writes it (opacity 0-1, visibility, quoted names).
    const auto snap = core::LabelTable::load(write(dir, "snap.txt",
        "################################################\n"
        "# ITK-SnAP Label Description File\n"
        "#    IDX   -R-  -G-  -B-  -A--  VIS MSH  LABEL\n"
        "    0     0    0    0        0  0  0    \"Clear Label\"\n"
        "    1   255    0    0        1  1  1    \"Liver\"\n"
        "    2     0  255    0      0.5  0  1    \"Left kidney\"\n"));
    EXPECT_EQ(snap.format(), "ITK-SNAP label descriptions");
    ASSERT_EQ(snap.entries().size(), 2u);
    EXPECT_EQ(snap.find(0), nullptr);  // the background is never drawn
    EXPECT_EQ(snap.find(1)->name, "Liver");
    EXPECT_EQ(snap.find(1)->rgba, (std::array<std::uint8_t, 4>{255, 0, 0, 255}));
    EXPECT_EQ(snap.find(2)->name, "Left kidney");
    EXPECT_EQ(snap.find(2)->rgba[3], 128);
    EXPECT_FALSE(snap.find(2)->visible);
    // FreeSurfer's LUT: its A is a transparency (0: opaque).
    const auto fs = core::LabelTable::load(write(dir, "FreeSurferColorLUT.txt",
        "#No. Label Name:                            R   G   B   A\n"
        "0   Unknown                                 0   0   0   0\n"
        "2   Left-Cerebral-White-Matter            245 245 245   0\n"
        "17  Left-Hippocampus                      220 216  20  64\n"));
    EXPECT_EQ(fs.format(), "FreeSurfer colour LUT");
    EXPECT_EQ(fs.find(2)->rgba, (std::array<std::uint8_t, 4>{245, 245, 245, 255}));
    EXPECT_EQ(fs.find(17)->name, "Left-Hippocampus");
    EXPECT_EQ(fs.find(17)->rgba[3], 191);
    // 3D Slicer's colour table: its A is an opacity.
    const auto slicer = core::LabelTable::load(write(dir, "seg.ctbl",
        "# Color table file /tmp/seg.ctbl\n# 3 values\n0 Background 0 0 0 0\n1 tissue 128 174 128 255\n"
        "5 bone 241 214 145 128\n"));
    EXPECT_EQ(slicer.format(), "3D Slicer colour table");
    EXPECT_EQ(slicer.find(5)->rgba, (std::array<std::uint8_t, 4>{241, 214, 145, 128}));
    // mricron's binary .lut: label i takes entry i.
    const auto mricron = core::LabelTable::load(mricronLut(dir, 768));
    EXPECT_EQ(mricron.format(), "mricron .lut");
    EXPECT_EQ(mricron.find(3)->rgba, (std::array<std::uint8_t, 4>{3, 252, 200, 255}));
    EXPECT_EQ(mricron.entries().size(), 255u);
}

TEST(ColourTables, BrokenLabelTablesAreRefusedWithTheFileAndLine) {
    test::TempDir dir;
    const auto refused = [&](const std::string& name, const std::string& text, const std::string& part) {
        const auto e = errorOf([&] { core::LabelTable::load(write(dir, name, text)); });
        EXPECT_NE(e.find(part), std::string::npos) << name << ": \"" << e << "\"";
    };
    refused("twice.txt", "1 a 1 2 3 0\n2 b 1 2 3 0\n1 c 1 2 3 0\n", "line 3: label 1 is already given on line 1");
    refused("colour.txt", "1 a 1 2 300 0\n", "line 1: colour component 300");
    refused("alpha.ctbl", "1 a 1 2 3 400\n", "alpha 400");
    refused("short.txt", "1 a 1 2\n", "line 1: expected");
    refused("fraction.txt", "1.5 a 1 2 3 0\n", "whole number");
    refused("snap.txt", "1 255 0 0 1.5 1 1 \"x\"\n", "opacity 1.5 is outside 0-1");
    refused("empty.txt", "# nothing here\n0 Unknown 0 0 0 0\n", "names no label");
    refused("garbage.lut", std::string("\x01\x02\0\x03", 4), "768 bytes");
    EXPECT_NE(errorOf([&] { core::LabelTable::load(dir.file("absent.txt")); }).find("cannot open"), std::string::npos);
}

TEST(ColourTables, LabelsMissingFromATableGetDistinctColoursAndAreReported) {
    auto t = core::LabelTable::generated({3, 1, 2});
    EXPECT_EQ(t.entries().size(), 3u);
    EXPECT_NE(t.find(1)->rgba, t.find(2)->rgba);
    EXPECT_NE(t.find(2)->rgba, t.find(3)->rgba);
    EXPECT_EQ(t.addMissing({0, 1, 9, 4, 9}), (std::vector<int>{4, 9}));
    EXPECT_EQ(t.find(9)->name, "label 9");
    t.setVisible(9, false);
    EXPECT_FALSE(t.find(9)->visible);
}
