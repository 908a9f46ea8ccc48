// Display models: MCOP ray geometry (thesis Eq. 5.1), off-axis views, s(z), quilt layout and
// naming, built-in profiles, and bad profiles or impossible sizes.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/camera/DisplayModel.h"
#include "core/base/Error.h"
#include "core/image/QuiltLayout.h"

using namespace hvx;

namespace {
core::View::ScreenRays displayFrame() {
    core::View::ScreenRays s;
    s.centre = {10, 20, 30};
    s.right = {1, 0, 0};
    s.up = {0, 0, 1};  // display z (towards the viewer) is then -y: anterior
    s.widthMm = 400;
    s.heightMm = 300;
    s.viewer = {0, 50, 1000};
    s.projector = {-120, 0, -700};
    return s;
}
}  // namespace

TEST(DisplayModel, McopRayOriginsFollowEquation51) {
    auto s = displayFrame();
    for (double eta : {1.0, 0.5}) {
        s.eta = eta;
        const auto v = core::View::screenView(s, 40, 30);
        for (int x : {0, 17, 39})
            for (int y : {0, 29}) {
                glm::dvec3 o, d;
                v.ray(x, y, o, d);
                // By hand: S on the screen, O by Eq. 5.1 (display coordinates), then to patient space.
                const glm::dvec3 S(((x + 0.5) / 40 - 0.5) * 400, (0.5 - (y + 0.5) / 30) * 300, 0);
                const glm::dvec3 E = s.projector, V = s.viewer;
                const double ox = (1 - eta) * V.x + eta * (E.x + (S.x - E.x) / (S.z - E.z) * (V.z - E.z));
                const glm::dvec3 O(ox, V.y, V.z);
                const glm::dvec3 want = s.centre + s.right * O.x + s.up * O.y + s.normal() * O.z;
                EXPECT_NEAR(glm::length(o - want), 0.0, 1e-9) << "eta " << eta << " pixel " << x << "," << y;
                // The ray passes through the screen point S.
                const glm::dvec3 Sw = s.centre + s.right * S.x + s.up * S.y;
                EXPECT_NEAR(glm::length(glm::cross(Sw - o, d)), 0.0, 1e-6);
            }
    }
    // With eta = 1 the horizontal ray lies on the projector's beam E -> S, extended to the viewer line.
    s.eta = 1.0;
    const auto v = core::View::screenView(s, 40, 30);
    glm::dvec3 o, d;
    v.ray(5, 10, o, d);
    const glm::dvec3 E = s.centre + s.right * s.projector.x + s.normal() * s.projector.z;
    const glm::dvec3 beam = glm::normalize(glm::dvec3(glm::dot(o - E, s.right), 0, glm::dot(o - E, s.normal())));
    const glm::dvec3 ray = glm::normalize(glm::dvec3(glm::dot(d, s.right), 0, glm::dot(d, s.normal())));
    EXPECT_NEAR(std::abs(glm::dot(beam, ray)), 1.0, 1e-9);
}

TEST(DisplayModel, EtaZeroIsAPinholeAtTheViewer) {
    auto s = displayFrame();
    s.eta = 0.0;
    const auto v = core::View::screenView(s, 40, 30);
    const glm::dvec3 V = s.centre + s.right * s.viewer.x + s.up * s.viewer.y + s.normal() * s.viewer.z;
    for (int x : {0, 20, 39})
        for (int y : {0, 15, 29}) {
            glm::dvec3 o, d;
            v.ray(x, y, o, d);
            EXPECT_NEAR(glm::length(o - V), 0.0, 1e-9) << "every ray starts at V";
        }
    // An on-axis viewer gives the plain pinhole of the same field of view.
    s.viewer = {0, 0, 1000};
    const auto c = core::View::screenView(s, 40, 30);
    core::View p = c;
    p.model = core::View::Model::Pinhole;
    p.fovYDegrees = glm::degrees(2 * std::atan(150.0 / 1000.0));
    for (int x : {0, 20, 39}) {
        glm::dvec3 o1, d1, o2, d2;
        c.ray(x, 7, o1, d1);
        p.ray(x, 7, o2, d2);
        EXPECT_NEAR(glm::length(d1 - d2), 0.0, 1e-9);
    }
}

TEST(DisplayModel, BuiltInProfilesMatchTheThesisDisplays) {
    const auto small = core::DisplayModel::load("holovizio-96");
    EXPECT_EQ(small.viewCount(), 96);
    EXPECT_EQ(small.viewWidthPx(), 320);
    EXPECT_DOUBLE_EQ(small.pixelSizeMm, 1.25);
    EXPECT_DOUBLE_EQ(small.beamAngleDegrees, 0.8);
    const auto large = core::DisplayModel::load("holovizio-72");
    EXPECT_EQ(large.viewCount(), 72);
    EXPECT_EQ(large.viewWidthPx() * large.viewHeightPx() * large.viewCount(), 800 * 600 * 72);  // 35 megapixels
    EXPECT_DOUBLE_EQ(large.screenWidthMm, 1600);
    EXPECT_DOUBLE_EQ(large.fieldOfViewDegrees, 50);
    // s(z) = s0 + 2|z| tan(phi/2)
    EXPECT_DOUBLE_EQ(large.accuracy(0), 1.5);
    EXPECT_NEAR(large.accuracy(-200), 1.5 + 400 * std::tan(glm::radians(0.4)), 1e-12);
    EXPECT_EQ(large.accuracy(200), large.accuracy(-200));
    for (const auto& name : {"looking-glass-go", "looking-glass-portrait", "looking-glass-16", "looking-glass-32",
                             "looking-glass-65", "stereo-side-by-side", "stereo-anaglyph", "stereo-column-interleave"})
        EXPECT_NO_THROW(core::DisplayModel::load(name)) << name;
    // Projectors span the field of view, symmetric about the screen centre.
    EXPECT_NEAR(large.projectorPosition(0).x, -large.projectorPosition(71).x, 1e-9);
    EXPECT_LT(large.projectorPosition(0).z, 0.0);
}

// Default framing, worked by hand from the Looking Glass Portrait's profile: a box of 200 mm
// across, 150 mm up and 180 mm deep fills 95 % of the screen's width or height, whichever comes
// first; its depth is compressed into the range where s(z) <= 2 s(0), i.e. |z| <= s0 / (2 tan(phi/2))
// with s0 the screen height over the view height and phi the view cone over (views - 1).
TEST(DisplayModel, FramingFillsTheWidthAndFitsTheDepthIntoTheSharpRange) {
    const auto lg = core::DisplayModel::load("looking-glass-portrait");
    std::vector<glm::dvec3> box;
    for (int c = 0; c < 8; ++c) box.push_back({c & 1 ? 110.0 : -90.0, c & 2 ? 40.0 : -140.0, c & 4 ? 80.0 : -70.0});
    // Across: x (200 mm); up: z (150 mm); depth: y (180 mm).
    const auto f = lg.frame(box, {1, 0, 0}, {0, 0, 1});
    const double s0 = lg.screenHeightMm / lg.viewHeightPx();
    const double phi = glm::radians(lg.viewConeDegrees / (lg.viewCount() - 1));
    const double range = s0 / (2.0 * std::tan(phi / 2.0));
    EXPECT_NEAR(lg.depthRangeMm(), range, 1e-9);
    EXPECT_NEAR(lg.accuracy(range), 2.0 * lg.accuracy(0.0), 1e-9);
    const double expected = std::min(0.95 * lg.screenWidthMm / 200.0, 0.95 * lg.screenHeightMm / 150.0);
    EXPECT_NEAR(f.scale, expected, 1e-12);
    EXPECT_NEAR(f.depthScale, std::min(expected, 2.0 * range / 180.0), 1e-12);
    EXPECT_LT(f.depthScale, f.scale) << "a 180 mm deep head does not fit a Looking Glass's depth without compression";
    EXPECT_NEAR(f.centre.x, 10.0, 1e-9);
    EXPECT_NEAR(f.centre.y, -50.0, 1e-9);
    EXPECT_NEAR(f.centre.z, 5.0, 1e-9);
    const auto same = lg.frame(box, {1, 0, 0}, {0, 0, 1}, true);
    EXPECT_EQ(same.scale, same.depthScale);
    EXPECT_NEAR(same.scale, f.depthScale, 1e-12);
    // The views place their viewers by the two scales: across by one, along the normal by the other.
    const auto views = lg.views(f.centre, {1, 0, 0}, {0, 0, 1}, 1.0, 30, 40, f.scale, f.depthScale);
    EXPECT_NEAR(views.front().screen.viewer.z, lg.observerDistanceMm / f.depthScale, 1e-9);
    EXPECT_NEAR(views.front().screen.widthMm, lg.screenWidthMm / f.scale, 1e-9);
}

TEST(DisplayModel, QuiltViewsAreShiftedLeftToRightAndTilesStartBottomLeft) {
    const auto lg = core::DisplayModel::load("looking-glass-portrait");
    const auto views = lg.views({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 1.0, 42, 56);
    ASSERT_EQ(views.size(), 48u);
    for (std::size_t i = 1; i < views.size(); ++i) {
        EXPECT_GT(views[i].screen.viewer.x, views[i - 1].screen.viewer.x) << "view 0 is the leftmost";
        EXPECT_EQ(views[i].screen.centre, views[0].screen.centre) << "shifted frustums share the screen, never toed in";
    }
    core::QuiltLayout q{8, 6, 4, 3, 0.75};
    std::vector<core::RenderImage> tiles;
    for (int i = 0; i < 48; ++i) {
        core::RenderImage t;
        t.width = 4;
        t.height = 3;
        t.rgba.assign(12, glm::vec4(float(i) / 47.0f, 0, 0, 1));
        t.depth.assign(12, float(i));
        tiles.push_back(t);
    }
    const auto quilt = q.assemble(tiles);
    ASSERT_EQ(quilt.width, 32);
    ASSERT_EQ(quilt.height, 18);
    auto viewAt = [&](int x, int y) { return int(std::lround(quilt.depth[std::size_t(y) * 32 + std::size_t(x)])); };
    EXPECT_EQ(viewAt(0, 17), 0) << "view 0: bottom-left tile";
    EXPECT_EQ(viewAt(31, 17), 7) << "first row runs left to right";
    EXPECT_EQ(viewAt(0, 14), 8) << "then the row above";
    EXPECT_EQ(viewAt(31, 0), 47) << "last view: top-right";
    EXPECT_EQ(q.fileName("/tmp/brain.png"), "/tmp/brain_qs8x6a0.75.png");
    EXPECT_EQ((core::QuiltLayout{5, 9, 1, 1, 1.7778}.fileName("x")), "x_qs5x9a1.7778.png");
    tiles.pop_back();
    EXPECT_THROW(q.assemble(tiles), core::Error);
}

TEST(DisplayModel, BadProfilesAndImpossibleSizesGiveClearErrors) {
    auto expectError = [](const std::string& json, const std::string& words) {
        try {
            core::DisplayModel::parse(json, "test.json");
            ADD_FAILURE() << "accepted: " << json;
        } catch (const core::Error& e) {
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("test.json"), std::string::npos) << e.what();
        }
    };
    expectError("{", "not valid JSON");
    expectError("[1,2]", "JSON object");
    expectError(R"({"kind":"hologram","screenSizeMm":[1,1]})", "kind must be");
    expectError(R"({"kind":"projector-array","screenSizeMm":[500,300]})", "projectors is missing");
    expectError(R"({"kind":"projector-array","screenSizeMm":[500,300],"projectors":0,"projectorResolution":[320,240],
                   "pixelSizeMm":1,"beamAngleDegrees":1,"fieldOfViewDegrees":50,"projectorDistanceMm":700})",
                "projectors must be between");
    expectError(R"({"kind":"projector-array","screenSizeMm":[500],"projectors":4})", "screenSizeMm must be a pair");
    expectError(R"({"kind":"lenticular","screenSizeMm":[100,100],"quilt":[8,6],"quiltSize":[4,4],"aspect":1,"viewConeDegrees":40})",
                "too small");
    expectError(R"({"kind":"stereo","screenSizeMm":[100,100],"layout":"wiggle","viewSize":[10,10],"eyeSeparationMm":63})",
                "layout must be");
    EXPECT_THROW(core::DisplayModel::load("no-such-display"), core::Error);
    const auto d = core::DisplayModel::load("holovizio-72");
    EXPECT_THROW(d.views({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 1.5), core::Error) << "eta outside [0, 1]";
    EXPECT_THROW(d.views({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 1.0, 100000, 100000), core::Error) << "impossible size";
    EXPECT_THROW(d.views({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 1.0, 0, 0, -1.0), core::Error) << "negative scale";
}

#include "core/image/DviPacker.h"
#include "core/image/StereoComposer.h"

namespace {
core::RenderImage flat(int w, int h, glm::vec4 c) {
    core::RenderImage im;
    im.width = w;
    im.height = h;
    im.rgba.assign(std::size_t(w) * std::size_t(h), c);
    im.depth.assign(im.rgba.size(), 1.0f);
    return im;
}
}  // namespace

TEST(DisplayModel, StereoLayoutsPutEachEyeWhereTheDisplayExpectsIt) {
    const auto left = flat(4, 2, {1, 0, 0, 1}), right = flat(4, 2, {0, 0, 1, 1});
    using L = core::DisplayModel::StereoLayout;
    const auto sbs = core::StereoComposer::compose(L::SideBySide, left, right);
    EXPECT_EQ(sbs.width, 8);
    EXPECT_EQ(sbs.rgba[0], left.rgba[0]);
    EXPECT_EQ(sbs.rgba[7], right.rgba[0]);
    const auto cols = core::StereoComposer::compose(L::ColumnInterleave, left, right);
    EXPECT_EQ(cols.rgba[0], left.rgba[0]) << "even columns: left eye";
    EXPECT_EQ(cols.rgba[1], right.rgba[0]);
    const auto ana = core::StereoComposer::compose(L::Anaglyph, flat(4, 2, {1, 1, 1, 1}), flat(4, 2, {0, 0.5f, 0.25f, 1}));
    EXPECT_NEAR(ana.rgba[0].r, 1.0f, 1e-6) << "red: the left eye's luminance";
    EXPECT_EQ(ana.rgba[0].g, 0.5f);
    EXPECT_EQ(ana.rgba[0].b, 0.25f);
    EXPECT_THROW(core::StereoComposer::compose(L::SideBySide, left, flat(3, 2, {})), core::Error);
    // The stereo views are the two eyes, 63 mm apart, left first.
    const auto pair = core::DisplayModel::load("stereo-side-by-side").views({0, 0, 0}, {1, 0, 0}, {0, 0, 1});
    ASSERT_EQ(pair.size(), 2u);
    EXPECT_NEAR(pair[1].screen.viewer.x - pair[0].screen.viewer.x, 63.0, 1e-9);
}

TEST(DisplayModel, DviLayoutPacksSixteenProjectorsPerFrameWithTheirIdsInTheHeader) {
    std::vector<core::RenderImage> projectors;
    for (int i = 0; i < 20; ++i) projectors.push_back(flat(320, 240, {float(i) / 20.0f, 0.5f, 0.25f, 1}));
    const auto frames = core::DviPacker::pack(projectors);
    ASSERT_EQ(frames.size(), 2u);
    EXPECT_EQ(frames[0].width, 1280);
    EXPECT_EQ(frames[0].height, 1024);
    EXPECT_EQ(core::DviPacker::decodeId(frames[0], 0), 0);
    EXPECT_EQ(core::DviPacker::decodeId(frames[0], 15), 15);
    // The header's codes survive the PNG's sRGB encoding byte for byte (ImageWriter's formula).
    for (int k = 0; k < 256; ++k) EXPECT_EQ(core::DviPacker::byteOfLinear(core::DviPacker::linearOfByte(k)), k) << k;
    EXPECT_EQ(core::DviPacker::decodeId(frames[1], 3), 19);
    EXPECT_EQ(core::DviPacker::decodeId(frames[1], 4), -1) << "unused block";
    // Tile 5 of frame 0 (row 1, column 1) holds projector 5.
    EXPECT_EQ(frames[0].rgba[std::size_t(64 + 240 + 10) * 1280 + 320 + 10], projectors[5].rgba[0]);
    projectors.push_back(flat(100, 100, {}));
    EXPECT_THROW(core::DviPacker::pack(projectors), core::Error);
}

#include "core/image/ProjectorCorrection.h"

namespace {
std::string grid(float dx, float dy) {
    std::string o = "[";
    for (int i = 0; i < 4; ++i) o += std::string(i ? "," : "") + "[" + std::to_string(dx) + "," + std::to_string(dy) + "]";
    return o + "]";
}
std::string ramp(bool invert) {
    std::string o = "[";
    for (int k = 0; k < 256; ++k) o += std::string(k ? "," : "") + std::to_string(invert ? 1.0 - k / 255.0 : k / 255.0);
    return o + "]";
}
}  // namespace

TEST(DisplayModel, CorrectionPassWarpsAndRecoloursEachProjector) {
    core::RenderImage img = flat(8, 6, {0, 0, 0, 1});
    img.rgba[std::size_t(3) * 8 + 4] = {1, 0.5f, 0.25f, 1};  // a marker at (4, 3)
    // Identity: no change.
    const auto identity = core::ProjectorCorrection::parse(R"({"projectors": [{"grid": [2, 2], "offsets": )" + grid(0, 0) +
                                                               "}]}",
                                                           "identity");
    EXPECT_EQ(identity.apply(img, 5).rgba, img.rgba) << "one entry applies to every projector";
    // A uniform offset of (+2, -1): output pixel p shows input p + (2, -1), so the marker moves to (2, 4).
    const auto shift = core::ProjectorCorrection::parse(R"({"projectors": [{"grid": [2, 2], "offsets": )" + grid(2, -1) +
                                                            "}]}",
                                                        "shift");
    const auto moved = shift.apply(img, 0);
    EXPECT_EQ(moved.rgba[std::size_t(4) * 8 + 2], img.rgba[std::size_t(3) * 8 + 4]);
    EXPECT_EQ(moved.rgba[std::size_t(3) * 8 + 4], glm::vec4(0, 0, 0, 1));
    // An inverting colour table.
    const auto invert = core::ProjectorCorrection::parse(
        R"({"projectors": [{"lut": {"r": )" + ramp(true) + R"(, "g": )" + ramp(true) + R"(, "b": )" + ramp(false) + "}}]}",
        "invert");
    const auto recoloured = invert.apply(img, 0);
    EXPECT_NEAR(recoloured.rgba[std::size_t(3) * 8 + 4].r, 0.0f, 1e-5f);
    EXPECT_NEAR(recoloured.rgba[std::size_t(3) * 8 + 4].g, 0.5f, 1e-2f);
    EXPECT_NEAR(recoloured.rgba[std::size_t(3) * 8 + 4].b, 0.25f, 1e-2f);
    EXPECT_NEAR(recoloured.rgba[0].r, 1.0f, 1e-5f);
    // Bad files.
    EXPECT_THROW(core::ProjectorCorrection::parse("{}", "x"), core::Error);
    EXPECT_THROW(core::ProjectorCorrection::parse(R"({"projectors": [{"grid": [2, 2], "offsets": [[0, 0]]}]})", "x"), core::Error);
    EXPECT_THROW(core::ProjectorCorrection::parse(R"({"projectors": [{"lut": {"r": [0.5]}}]})", "x"), core::Error);
    EXPECT_THROW(core::ProjectorCorrection::parse("[", "x"), core::Error);
    EXPECT_THROW(core::ProjectorCorrection::load("/nonexistent/correction.json"), core::Error);
}
