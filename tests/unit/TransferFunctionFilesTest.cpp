// Transfer-function files: Holovox JSON round trip, 3D Slicer presets.xml and ParaView colour
// maps, and broken or hostile files that must give one clear error.
#include <gtest/gtest.h>

#include <QFile>
#include <QString>

#include <fstream>

#include "core/base/Error.h"
#include "tests/support/TempDir.h"
#include "ui/TransferFunctionFiles.h"

using namespace hvx;

namespace {
QString write(const test::TempDir& dir, const std::string& name, const std::string& text) {
    std::ofstream(dir.file(name), std::ios::binary) << text;
    return QString::fromStdString(dir.file(name));
}
// Slicer's own CT-AAA preset line (presets.xml in 3D Slicer's VolumeRendering module).
const char* kSlicer = R"(<?xml version="1.0" encoding="UTF-8"?>
<root>
  <VolumeProperty name="CT-AAA" interpolation="1" shade="1" diffuse="0.9" specular="0.2" ambient="0.1"
    specularPower="10" scalarOpacity="12 -3024 0 143.556 0 166.222 0.686275 214.389 0.696078 419.736 0.833333 3071 0.803922"
    gradientOpacity="4 0 1 255 1"
    colorTransfer="24 -3024 0 0 0 143.556 0.615686 0.356863 0.184314 166.222 0.882353 0.603922 0.290196 214.389 1 1 1 419.736 1 0.937033 0.954531 3071 0.827451 0.658824 1"/>
  <VolumeProperty name="CT-Bone" scalarOpacity="8 -3024 0 -16.4458 0 641.385 0.715686 3071 0.705882"
    colorTransfer="16 -3024 0 0 0 -16.4458 0.729412 0.254902 0.301961 641.385 0.905882 0.815686 0.552941 3071 1 1 1"/>
</root>)";
}  // namespace

TEST(TransferFunctionFiles, HolovoxJsonRoundTripsInPhysicalUnits) {
    test::TempDir dir;
    core::TransferFunctionSpec s;
    s.opacity = {{-1000, 0}, {300, 0.4}, {2000, 0.9}};
    s.colours = {{-1000, {0, 0, 0}}, {400, {1, 0.5, 0.25}}};
    const QString path = QString::fromStdString(dir.file("tf.json"));
    ui::TransferFunctionFiles::save(s, path);
    const auto back = ui::TransferFunctionFiles::load(path);
    ASSERT_EQ(back.opacity.size(), 3u);
    EXPECT_DOUBLE_EQ(back.opacity[1].value, 300);
    EXPECT_DOUBLE_EQ(back.opacity[1].alpha, 0.4);
    EXPECT_DOUBLE_EQ(back.colours[1].rgb.g, 0.5);
    // Stored units of a volume with slope 2, intercept -1024: (300 + 1024) / 2 = 662.
    const auto stored = ui::TransferFunctionFiles::toStored(back, 2.0, -1024.0);
    EXPECT_DOUBLE_EQ(stored.opacity[1].value, 662);
    EXPECT_DOUBLE_EQ(ui::TransferFunctionFiles::toPhysical(stored, 2.0, -1024.0).opacity[1].value, 300);
    EXPECT_TRUE(back.gradientOpacity.empty());
    // A gradient opacity curve (HU per mm) goes and comes back; in stored units its magnitudes
    // are divided by the slope (a 2-HU stored step is 1 stored unit).
    s.gradientOpacity = {{0, 0.1}, {40, 1}};
    ui::TransferFunctionFiles::save(s, path);
    const auto withGradient = ui::TransferFunctionFiles::load(path);
    ASSERT_EQ(withGradient.gradientOpacity.size(), 2u);
    EXPECT_DOUBLE_EQ(withGradient.gradientOpacity[0].scale, 0.1);
    EXPECT_DOUBLE_EQ(withGradient.gradientOpacity[1].magnitude, 40);
    EXPECT_DOUBLE_EQ(ui::TransferFunctionFiles::toStored(withGradient, 2.0, -1024.0).gradientOpacity[1].magnitude, 20);
    std::ofstream(dir.file("bad.json")) << R"({"format": "holovox-transfer-function", "version": 1, "opacity": [[0, 0.5]],)"
                                        << R"( "colours": [[0, 1, 1, 1]], "gradientOpacity": [[10, 1.5]]})";
    try {
        ui::TransferFunctionFiles::load(QString::fromStdString(dir.file("bad.json")));
        FAIL() << "a gradient opacity scale of 1.5 was accepted";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("scale of 0 to 1"), std::string::npos) << e.what();
    }
    // A refraction curve (physical values) goes and comes back, its values converted as the
    // opacity's; an index outside [0.25, 4] is refused, naming the file.
    s.refraction = {{-1000, 1.0}, {300, 1.33}};
    ui::TransferFunctionFiles::save(s, path);
    const auto withRefraction = ui::TransferFunctionFiles::load(path);
    ASSERT_EQ(withRefraction.refraction.size(), 2u);
    EXPECT_DOUBLE_EQ(withRefraction.refraction[1].index, 1.33);
    EXPECT_DOUBLE_EQ(ui::TransferFunctionFiles::toStored(withRefraction, 2.0, -1024.0).refraction[1].value, 662);
    std::ofstream(dir.file("bad.json")) << R"({"format": "holovox-transfer-function", "version": 1, "opacity": [[0, 0.5]],)"
                                        << R"( "colours": [[0, 1, 1, 1]], "refraction": [[10, 0]]})";
    try {
        ui::TransferFunctionFiles::load(QString::fromStdString(dir.file("bad.json")));
        FAIL() << "a refraction index of 0 was accepted";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("refraction index must be between 0.25 and 4"), std::string::npos) << e.what();
    }
}

TEST(TransferFunctionFiles, ReadsSlicerVolumePropertyPresets) {
    test::TempDir dir;
    const auto presets = ui::TransferFunctionFiles::readSlicerPresets(write(dir, "presets.xml", kSlicer));
    ASSERT_EQ(presets.size(), 2u);
    EXPECT_EQ(presets[0].first, "CT-AAA");
    const auto& aaa = presets[0].second;
    ASSERT_EQ(aaa.opacity.size(), 6u);
    ASSERT_EQ(aaa.colours.size(), 6u);
    EXPECT_DOUBLE_EQ(aaa.opacity[2].value, 166.222);
    EXPECT_DOUBLE_EQ(aaa.opacity[2].alpha, 0.686275);
    EXPECT_DOUBLE_EQ(aaa.colours[3].rgb.r, 1.0);
    EXPECT_EQ(presets[1].first, "CT-Bone");
    // Slicer's usual gradientOpacity="4 0 1 255 1" is flat: read, and it scales nothing.
    ASSERT_EQ(aaa.gradientOpacity.size(), 2u);
    EXPECT_DOUBLE_EQ(aaa.gradientOpacity[1].magnitude, 255);
    EXPECT_FALSE(aaa.build(-3024, 3071, 1.0).hasGradientOpacity());
    EXPECT_TRUE(presets[1].second.gradientOpacity.empty());
}

TEST(TransferFunctionFiles, ReadsParaViewColourMapsRescaledToTheVolume) {
    test::TempDir dir;
    const auto current = core::TransferFunctionSpec{{{0, 0}, {100, 1}}, {{0, {0, 0, 0}}}, {}, {}};
    const auto map = ui::TransferFunctionFiles::readParaView(
        write(dir, "cool.json", R"([{"Name":"Cool to Warm","ColorSpace":"Diverging",
           "RGBPoints":[-1, 0.23, 0.299, 0.754, 0, 0.865, 0.865, 0.865, 1, 0.706, 0.016, 0.150]}])"),
        0.0, 4000.0, current);
    ASSERT_EQ(map.colours.size(), 3u);
    EXPECT_DOUBLE_EQ(map.colours[1].value, 2000.0) << "[-1, 1] spread over [0, 4000]";
    EXPECT_DOUBLE_EQ(map.colours[2].rgb.r, 0.706);
    EXPECT_EQ(map.opacity.size(), 2u) << "no opacity points: the current curve stays";
}

TEST(TransferFunctionFiles, BrokenAndHostileFilesGiveOneClearError) {
    test::TempDir dir;
    auto expectError = [&](const std::string& name, const std::string& text, const std::string& words,
                           bool slicer = false, bool paraview = false) {
        const QString path = write(dir, name, text);
        try {
            if (slicer) ui::TransferFunctionFiles::readSlicerPresets(path);
            else if (paraview) ui::TransferFunctionFiles::readParaView(path, 0, 1, {{{0, 0}}, {{0, {0, 0, 0}}}, {}, {}});
            else ui::TransferFunctionFiles::load(path);
            ADD_FAILURE() << name << " was accepted";
        } catch (const core::Error& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(name), std::string::npos) << what;
            EXPECT_NE(what.find(words), std::string::npos) << name << ": " << what;
        }
    };
    expectError("empty.json", "", "not valid JSON");
    expectError("truncated.json", R"({"format":"holovox-transfer-function","version":1,"opacity":[[0,)", "not valid JSON");
    expectError("other.json", R"({"format":"something-else"})", "not a Holovox transfer function");
    expectError("alpha.json", R"({"format":"holovox-transfer-function","version":1,"opacity":[[0,7]],"colours":[[0,0,0,0]]})",
                "opacity must be between 0 and 1");
    expectError("strings.json", R"({"format":"holovox-transfer-function","version":1,"opacity":[["a","b"]],"colours":[]})",
                "opacity point");
    expectError("nopoints.json", R"({"format":"holovox-transfer-function","version":1,"opacity":[],"colours":[]})",
                "no opacity points");
    expectError("count.xml", R"(<root><VolumeProperty name="X" scalarOpacity="6 0 0 1" colorTransfer="4 0 0 0 0"/></root>)",
                "announces 6 numbers", true);
    expectError("nan.xml", R"(<root><VolumeProperty name="X" scalarOpacity="2 0 nan" colorTransfer="4 0 0 0 0"/></root>)",
                "not a number", true);
    expectError("broken.xml", "<root><VolumeProperty name=\"X\"", "not valid XML", true);
    expectError("none.xml", "<root/>", "no VolumeProperty", true);
    expectError("norgb.json", R"([{"Name":"x"}])", "RGBPoints", false, true);
    EXPECT_THROW(ui::TransferFunctionFiles::load(QString::fromStdString(dir.file("missing.json"))), core::Error);
}
