// Region statistics (holovox-cli measure; the reading tools' ROIs) against a brute-force pass
// over the dense volume with the same rule (a voxel counts when its centre lies in the region):
// isotropic and anisotropic, sheared and rescaled volumes, boxes cut by the volume's edge, many
// small bricks. A sphere of known radius has the analytic volume; degenerate and outside
// regions are refused with a sentence; bricks stored without their values make the figures
// approximate, and say so.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <tuple>
#include <memory>

#include <glm/matrix.hpp>

#include "core/base/Error.h"
#include "core/base/JobContext.h"
#include "core/octree/OctreeBuilder.h"
#include "core/reference/RegionStatistics.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/ErrorOf.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
struct Brute {
    std::uint64_t voxels = 0;
    double mean = 0, sd = 0, min = 0, max = 0;
};

Brute bruteForce(const core::VolumeGeometry& g, const test::DenseVolume& v, const core::MeasureRegion& r) {
    Brute b;
    std::vector<double> in;
    const glm::dmat4 m = g.indexToPatient();
    for (std::uint32_t k = 0; k < g.dims[2]; ++k)
        for (std::uint32_t j = 0; j < g.dims[1]; ++j)
            for (std::uint32_t i = 0; i < g.dims[0]; ++i)
                if (r.contains(glm::dvec3(m * glm::dvec4(i, j, k, 1.0))))
                    in.push_back(v.values[(std::size_t(k) * g.dims[1] + j) * g.dims[0] + i] * g.rescaleSlope +
                                 g.rescaleIntercept);
    b.voxels = in.size();
    if (in.empty()) return b;
    double sum = 0;
    b.min = b.max = in[0];
    for (double x : in) sum += x, b.min = std::min(b.min, x), b.max = std::max(b.max, x);
    b.mean = sum / double(in.size());
    double ss = 0;
    for (double x : in) ss += (x - b.mean) * (x - b.mean);
    b.sd = std::sqrt(ss / double(in.size()));
    return b;
}

/// A CT-like volume: noise around -800 HU, and a ball of 1000 HU (stored 2024 with intercept
/// -1024) of `radius` mm around the patient point `centre`.
test::DenseVolume ballVolume(const core::VolumeGeometry& g, const glm::dvec3& centre, double radius, unsigned seed) {
    test::DenseVolume v;
    v.dims = g.dims;
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0, 30);
    const glm::dmat4 m = g.indexToPatient();
    for (std::uint32_t k = 0; k < g.dims[2]; ++k)
        for (std::uint32_t j = 0; j < g.dims[1]; ++j)
            for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
                const glm::dvec3 p(m * glm::dvec4(i, j, k, 1.0));
                const double hu = glm::length(p - centre) <= radius ? 1000.0 + std::round(noise(rng)) : -800.0 + std::round(noise(rng));
                v.values.push_back((hu - g.rescaleIntercept) / g.rescaleSlope);
            }
    return v;
}

std::string build(const test::TempDir& dir, const core::VolumeGeometry& g, const test::DenseVolume& v,
                  core::BuildOptions o = {}) {
    test::MemoryVoxelSource src(g, v);
    core::JobContext job;
    const std::string path = dir.file("v.hvo");
    core::OctreeBuilder(o).build(src, path, job);
    return path;
}

void expectSame(const core::RegionStatistics& s, const Brute& b, const std::string& what) {
    EXPECT_EQ(s.voxels, b.voxels) << what;
    EXPECT_NEAR(s.mean, b.mean, 1e-9 * std::max(1.0, std::abs(b.mean))) << what;
    EXPECT_NEAR(s.sd, b.sd, 1e-7 * std::max(1.0, b.sd)) << what;
    EXPECT_EQ(s.min, b.min) << what;
    EXPECT_EQ(s.max, b.max) << what;
}

core::VolumeGeometry ctGeometry(std::array<std::uint32_t, 3> dims, glm::dvec3 spacing) {
    core::VolumeGeometry g;
    g.dims = dims;
    g.spacing = spacing;
    g.origin = {-40.5, 12.25, -300.0};
    g.scalarType = core::ScalarType::Int16;
    g.rescaleSlope = 1.0;
    g.rescaleIntercept = -1024.0;
    g.modality = "CT";
    return g;
}
}  // namespace

TEST(RegionStatistics, SphereAndBoxesMatchABruteForcePassOnManySmallBricks) {
    test::TempDir dir;
    const auto g = ctGeometry({50, 44, 37}, {1, 1, 1});
    const glm::dvec3 centre = g.origin + glm::dvec3(24.3, 20.6, 17.2);
    const auto v = ballVolume(g, centre, 10.0, 1);
    core::BuildOptions o;
    o.brickSize = 8;  // a region spans dozens of bricks
    const auto reader = core::OctreeReader::open(build(dir, g, v, o));
    const auto sphere = core::MeasureRegion::sphere(centre, 10.0);
    const auto s = core::RegionStatistics::compute(*reader, sphere);
    expectSame(s, bruteForce(g, v, sphere), "sphere");
    EXPECT_TRUE(s.exact) << s.note;
    EXPECT_EQ(s.units, "HU");
    EXPECT_NEAR(s.mean, 1000.0, 3.0) << "the ball's HU, noise averaged out";
    // The voxel-centre count of a 10 mm ball in 1 mm voxels is within 2 % of 4/3 pi r^3.
    EXPECT_NEAR(s.volumeMm3, 4.0 / 3.0 * M_PI * 1000.0, 0.02 * 4.0 / 3.0 * M_PI * 1000.0);
    // A box across the ball's edge, and one cut by the volume's own faces (clamped, not refused:
    // the voxels inside the volume count, and the figures say that the region reached past it).
    const auto across = core::MeasureRegion::box(centre - 6.0, centre + glm::dvec3(12.0, 3.0, 8.0));
    const auto inside = core::RegionStatistics::compute(*reader, across);
    expectSame(inside, bruteForce(g, v, across), across.describe());
    EXPECT_EQ(inside.note, "");
    const auto cut = core::MeasureRegion::box(g.origin - 30.0, g.origin + glm::dvec3(7.0, 9.0, 11.0));
    const auto clamped = core::RegionStatistics::compute(*reader, cut);
    expectSame(clamped, bruteForce(g, v, cut), cut.describe());
    EXPECT_TRUE(clamped.exact) << "the figures of the part inside";
    EXPECT_NE(clamped.note.find("reaches outside the volume: only the voxels inside the volume are counted"),
              std::string::npos) << clamped.note;
    // A sphere reaching 1.3 voxels past the last layer holds centres of the grid continued past
    // the face: said; one that stops short of the last layer, or whose bounding box, not
    // itself, crosses a corner: not said.
    const glm::dvec3 far = g.origin + glm::dvec3(49.0, 20.0, 18.0);  // on the last layer along i
    const auto past = core::RegionStatistics::compute(*reader, core::MeasureRegion::sphere(far + glm::dvec3(-3.7, 0, 0), 5.0));
    EXPECT_NE(past.note.find("reaches outside"), std::string::npos) << past.note;
    const auto within = core::RegionStatistics::compute(*reader, core::MeasureRegion::sphere(far + glm::dvec3(-5.2, 0, 0), 5.0));
    EXPECT_EQ(within.note, "");
    const glm::dvec3 corner = g.origin + glm::dvec3(3.2, 3.2, 3.2);  // 5.5 mm from the corner voxel's centre
    const auto nearCorner = core::RegionStatistics::compute(*reader, core::MeasureRegion::sphere(corner, 4.0));
    EXPECT_EQ(nearCorner.note, "");
}

// A circle drawn on an axial slice (a disc one slice thick): the voxels of that slice whose
// centres lie within the radius, counted here by hand in the slice's own index plane.
/// An anisotropic CT (0.8 x 0.8 x 2 mm) with a ball centred on slice k = 18, in bricks of 8.
struct SliceCase {
    test::TempDir dir;
    core::VolumeGeometry g = ctGeometry({50, 44, 37}, {0.8, 0.8, 2.0});
    glm::dvec3 centre = g.origin + glm::dvec3(20.0, 17.6, 36.0);
    test::DenseVolume v;
    std::shared_ptr<const core::OctreeReader> reader;
    explicit SliceCase(unsigned seed) : v(ballVolume(g, centre, 9.0, seed)) {
        core::BuildOptions o;
        o.brickSize = 8;
        reader = core::OctreeReader::open(build(dir, g, v, o));
    }
};

TEST(RegionStatistics, ADiscOnASliceTakesThatSlicesVoxelsWithinItsRadius) {
    const SliceCase c(5);
    const auto& [g, centre, v] = std::tie(c.g, c.centre, c.v);
    const auto& reader = c.reader;
    const double radius = 6.3;
    const auto s = core::RegionStatistics::compute(*reader, core::MeasureRegion::disc(centre, {0, 0, 1}, radius, 2.0));
    std::uint64_t n = 0;
    double sum = 0;
    for (std::uint32_t j = 0; j < g.dims[1]; ++j)
        for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
            const double dx = g.origin.x + i * 0.8 - centre.x, dy = g.origin.y + j * 0.8 - centre.y;
            if (dx * dx + dy * dy > radius * radius) continue;
            ++n;
            sum += v.values[(std::size_t(18) * g.dims[1] + j) * g.dims[0] + i] - 1024.0;
        }
    EXPECT_EQ(s.voxels, n);
    EXPECT_NEAR(s.mean, sum / double(n), 1e-9 * std::abs(sum / double(n)));
    EXPECT_NEAR(s.areaMm2, double(n) * 0.8 * 0.8, 1e-9);
    EXPECT_NEAR(s.areaMm2, M_PI * radius * radius, 0.05 * M_PI * radius * radius) << "close to the circle's area";
    EXPECT_THROW(core::RegionStatistics::compute(*reader, core::MeasureRegion::disc(centre, {0, 0, 1}, radius, 0.0)),
                 core::Error);
    // Midway between slices 18 and 19, one slice thick: one layer of voxels, not both.
    const auto mid = core::RegionStatistics::compute(*reader, core::MeasureRegion::disc(centre + glm::dvec3(0, 0, 1.0),
                                                                                        {0, 0, 1}, radius, 2.0));
    EXPECT_EQ(mid.voxels, n);
}

TEST(RegionStatistics, AnisotropicShearedRescaledVolumeMatchesBruteForce) {
    test::TempDir dir;
    auto g = ctGeometry({40, 36, 30}, {0.7, 0.9, 2.5});
    const double tilt = 20.0 * M_PI / 180.0;  // a tilted gantry: k leans along y
    g.direction = glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, std::sin(tilt), std::cos(tilt)));
    g.rescaleSlope = 0.5;
    g.rescaleIntercept = -1024.0;
    const glm::dvec3 centre(g.indexToPatient() * glm::dvec4(20, 17, 14, 1));
    const auto v = ballVolume(g, centre, 9.0, 2);
    core::BuildOptions o;
    o.brickSize = 16;
    const auto reader = core::OctreeReader::open(build(dir, g, v, o));
    const auto sphere = core::MeasureRegion::sphere(centre + glm::dvec3(0.3, -0.2, 0.4), 9.0);
    const auto s = core::RegionStatistics::compute(*reader, sphere);
    expectSame(s, bruteForce(g, v, sphere), "sheared sphere");
    const glm::dmat3 step(g.direction[0] * g.spacing.x, g.direction[1] * g.spacing.y, g.direction[2] * g.spacing.z);
    EXPECT_NEAR(s.volumeMm3, double(s.voxels) * std::abs(glm::determinant(step)), 1e-6);
    const auto box = core::MeasureRegion::box(centre - glm::dvec3(5, 8, 13), centre + glm::dvec3(9, 2, 6));
    expectSame(core::RegionStatistics::compute(*reader, box), bruteForce(g, v, box), "sheared box");
}

TEST(RegionStatistics, DegenerateOutsideAndSubVoxelRegionsAreNamed) {
    test::TempDir dir;
    const auto g = ctGeometry({20, 20, 20}, {1, 1, 1});
    const auto v = ballVolume(g, g.origin + 10.0, 4.0, 3);
    const auto reader = core::OctreeReader::open(build(dir, g, v));
    const auto error = [&](const core::MeasureRegion& r) {
        try {
            core::RegionStatistics::compute(*reader, r);
        } catch (const core::Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(error(core::MeasureRegion::sphere(g.origin, 0.0)).find("no volume"), std::string::npos);
    EXPECT_NE(error(core::MeasureRegion::box(g.origin, g.origin + glm::dvec3(4, 0, 4))).find("no volume"),
              std::string::npos);
    EXPECT_NE(error(core::MeasureRegion::sphere(g.origin - 100.0, 5.0)).find("outside the volume"), std::string::npos);
    // Centred 0.7 voxel before the first voxel, reaching 0.2 voxel into the volume: it holds no
    // voxel centre, and is not said to be wholly outside (it had been).
    const std::string edge = error(core::MeasureRegion::sphere(g.origin + glm::dvec3(-0.7, 5.0, 5.0), 0.5));
    EXPECT_NE(edge.find("holds no voxel centre: its centre lies outside the volume"), std::string::npos) << edge;
    const auto tiny = core::RegionStatistics::compute(*reader, core::MeasureRegion::sphere(g.origin + 5.5, 0.2));
    EXPECT_EQ(tiny.voxels, 0u);
    EXPECT_FALSE(tiny.exact);
    EXPECT_NE(tiny.note.find("smaller than a voxel"), std::string::npos) << tiny.note;
    // A region of 1e19 mm holds the whole volume (its index range had overflowed to nothing).
    const auto huge = core::RegionStatistics::compute(*reader, core::MeasureRegion::sphere(g.origin, 1e19));
    EXPECT_EQ(huge.voxels, 8000u);
    EXPECT_NE(huge.note.find("reaches outside the volume"), std::string::npos) << huge.note;
    EXPECT_EQ(core::RegionStatistics::compute(*reader, core::MeasureRegion::box(g.origin - 1e20, g.origin + 1e20)).voxels, 8000u);
    // A volume turned 45 degrees about z: a sphere beyond its corner, within the corner's
    // patient-axis box, lies outside the volume (it had been called smaller than a voxel).
    auto turned = g;
    const double c = std::sqrt(0.5);
    turned.direction = glm::dmat3(glm::dvec3(c, c, 0), glm::dvec3(-c, c, 0), glm::dvec3(0, 0, 1));
    test::TempDir dir2;
    const auto oblique = core::OctreeReader::open(build(dir2, turned, v));
    const glm::dvec3 corner = turned.origin + glm::dvec3(0, 0, 10);  // voxel (0, 0, 10)
    const glm::dvec3 beyond = corner + 6.0 * glm::normalize(-(turned.direction[0] + turned.direction[1]));
    const std::string outside =
        test::errorOf([&] { core::RegionStatistics::compute(*oblique, core::MeasureRegion::sphere(beyond, 3.0)); });
    EXPECT_NE(outside.find("lies outside the volume"), std::string::npos) << outside;
    EXPECT_THROW(core::MeasureRegion::parse("sphere:1,2,3"), core::Error);
    EXPECT_THROW(core::MeasureRegion::parse("cube:1,2,3,4"), core::Error);
    EXPECT_THROW(core::MeasureRegion::parse("box:1,2,3,4,5,nan"), core::Error);
    EXPECT_THROW(core::MeasureRegion::parse("sphere:-0x3,-35,0,2"), core::Error) << "hex is not a coordinate";
    EXPECT_THROW(core::MeasureRegion::parse("sphere:-3,-35,0,2,"), core::Error) << "a trailing comma";
    EXPECT_EQ(core::MeasureRegion::parse("sphere:-3,-35,0,2.5e1").radius, 25.0);
    const auto parsed = core::MeasureRegion::parse("box:4,5,6,1,2,3");
    EXPECT_EQ(parsed.low, glm::dvec3(1, 2, 3));
    EXPECT_EQ(parsed.high, glm::dvec3(4, 5, 6));
}

TEST(RegionStatistics, BricksStoredWithoutTheirValuesMakeTheFiguresApproximate) {
    test::TempDir dir;
    const auto g = ctGeometry({32, 32, 32}, {1, 1, 1});
    const auto v = ballVolume(g, g.origin + 8.0, 5.0, 4);
    core::BuildOptions o;
    o.brickSize = 8;
    o.emptyBelow = -500.0;  // air-only bricks store no payload
    const auto reader = core::OctreeReader::open(build(dir, g, v, o));
    const auto s = core::RegionStatistics::compute(*reader, core::MeasureRegion::sphere(g.origin + 16.0, 12.0));
    EXPECT_FALSE(s.exact);
    EXPECT_GT(s.approximateVoxels, 0u);
    EXPECT_NE(s.note.find("--empty-below"), std::string::npos) << s.note;
    // Within the eight bricks that meet at the ball's centre every value is stored: exact there.
    const auto inside = core::RegionStatistics::compute(*reader, core::MeasureRegion::sphere(g.origin + 8.0, 3.0));
    EXPECT_TRUE(inside.exact) << inside.note;
    expectSame(inside, bruteForce(g, v, core::MeasureRegion::sphere(g.origin + 8.0, 3.0)), "ball bricks");
}

// A polygon drawn on a slice: a rectangle takes exactly the voxels of the box over the same
// slab (another containment rule, another code path), an L-shape those of its two boxes, and
// an outline with fewer than three corners or on one line is refused.
TEST(RegionStatistics, PolygonsTakeTheVoxelsOfTheBoxesTheyCover) {
    const SliceCase c(7);
    const auto& [g, centre] = std::tie(c.g, c.centre);
    const auto& reader = c.reader;
    // Corners between voxel centres (0.8 mm apart): no centre lies on an edge.
    const double z = centre.z, x0 = g.origin.x + 10.2, x1 = g.origin.x + 26.2, y0 = g.origin.y + 6.2, y1 = g.origin.y + 22.2;
    const auto rect = core::MeasureRegion::polygon({{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}}, {0, 0, 1}, 2.0);
    const auto sr = core::RegionStatistics::compute(*reader, rect);
    const auto sb = core::RegionStatistics::compute(*reader, core::MeasureRegion::box({x0, y0, z - 0.99}, {x1, y1, z + 0.99}));
    EXPECT_EQ(sr.voxels, sb.voxels);
    EXPECT_EQ(sr.voxels, 20u * 20u) << "20 x 20 voxel centres in 16 mm x 16 mm at 0.8 mm";
    EXPECT_DOUBLE_EQ(sr.mean, sb.mean);
    EXPECT_DOUBLE_EQ(sr.min, sb.min);
    EXPECT_DOUBLE_EQ(sr.max, sb.max);
    EXPECT_NEAR(sr.areaMm2, 16.0 * 16.0, 1e-9);
    // An L: the rectangle without its upper right quarter = two boxes.
    const double xm = g.origin.x + 18.2, ym = g.origin.y + 14.2;
    const auto l = core::MeasureRegion::polygon(
        {{x0, y0, z}, {x1, y0, z}, {x1, ym, z}, {xm, ym, z}, {xm, y1, z}, {x0, y1, z}}, {0, 0, -1}, 2.0);
    const auto sl = core::RegionStatistics::compute(*reader, l);
    const auto b1 = core::RegionStatistics::compute(*reader, core::MeasureRegion::box({x0, y0, z - 0.99}, {x1, ym, z + 0.99}));
    const auto b2 = core::RegionStatistics::compute(*reader, core::MeasureRegion::box({x0, ym, z - 0.99}, {xm, y1, z + 0.99}));
    EXPECT_EQ(sl.voxels, b1.voxels + b2.voxels);
    EXPECT_NEAR(sl.mean, (b1.mean * double(b1.voxels) + b2.mean * double(b2.voxels)) / double(b1.voxels + b2.voxels),
                1e-9 * std::abs(sl.mean));
    EXPECT_DOUBLE_EQ(sl.max, std::max(b1.max, b2.max));
    for (const auto& bad : {core::MeasureRegion::polygon({{x0, y0, z}, {x1, y1, z}}, {0, 0, 1}, 2.0),
                            core::MeasureRegion::polygon({{x0, y0, z}, {xm, ym, z}, {x1, y1, z}}, {0, 0, 1}, 2.0)}) {
        try {
            core::RegionStatistics::compute(*reader, bad);
            ADD_FAILURE() << "a polygon without area was measured";
        } catch (const core::Error& e) {
            EXPECT_NE(std::string(e.what()).find("no area"), std::string::npos) << e.what();
        }
    }
}

// An ellipse drawn on a slice, its axes turned 30 degrees from the volume's: the voxels of
// that slice inside it, counted here by hand; with equal semi-axes it is the circle of that
// radius; degenerate ones are refused.
TEST(RegionStatistics, AnEllipseOnASliceTakesThatSlicesVoxelsInside) {
    const SliceCase c(11);
    const auto& [g, centre, v] = std::tie(c.g, c.centre, c.v);
    const auto& reader = c.reader;
    const double a = 8.3, b = 4.1, turn = 30.0 * M_PI / 180.0;
    const glm::dvec3 axis(std::cos(turn), std::sin(turn), 0.0);
    const auto s = core::RegionStatistics::compute(*reader, core::MeasureRegion::ellipse(centre, {0, 0, 1}, axis, a, b, 2.0));
    std::uint64_t n = 0;
    double sum = 0, lo = 1e300, hi = -1e300;
    for (std::uint32_t j = 0; j < g.dims[1]; ++j)
        for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
            const double dx = g.origin.x + i * 0.8 - centre.x, dy = g.origin.y + j * 0.8 - centre.y;
            const double u = (dx * std::cos(turn) + dy * std::sin(turn)) / a, w = (-dx * std::sin(turn) + dy * std::cos(turn)) / b;
            if (u * u + w * w > 1.0) continue;
            ++n;
            const double hu = v.values[(std::size_t(18) * g.dims[1] + j) * g.dims[0] + i] - 1024.0;
            sum += hu;
            lo = std::min(lo, hu);
            hi = std::max(hi, hu);
        }
    ASSERT_GT(n, 100u);
    EXPECT_EQ(s.voxels, n);
    EXPECT_NEAR(s.mean, sum / double(n), 1e-9 * std::abs(sum / double(n)));
    EXPECT_DOUBLE_EQ(s.min, lo);
    EXPECT_DOUBLE_EQ(s.max, hi);
    EXPECT_NEAR(s.areaMm2, double(n) * 0.8 * 0.8, 1e-9);
    EXPECT_NEAR(s.areaMm2, M_PI * a * b, 0.06 * M_PI * a * b) << "close to the ellipse's area";
    const auto round = core::RegionStatistics::compute(*reader, core::MeasureRegion::ellipse(centre, {0, 0, 1}, axis, 6.3, 6.3, 2.0));
    const auto disc = core::RegionStatistics::compute(*reader, core::MeasureRegion::disc(centre, {0, 0, 1}, 6.3, 2.0));
    EXPECT_EQ(round.voxels, disc.voxels);
    EXPECT_DOUBLE_EQ(round.mean, disc.mean);
    for (const auto& bad : {core::MeasureRegion::ellipse(centre, {0, 0, 1}, axis, 0.0, 3.0, 2.0),
                            core::MeasureRegion::ellipse(centre, {0, 0, 1}, {0, 0, 1}, 3.0, 3.0, 2.0),
                            core::MeasureRegion::ellipse(centre, {0, 0, 1}, axis, 3.0, 3.0, 0.0)})
        EXPECT_THROW(core::RegionStatistics::compute(*reader, bad), core::Error) << bad.describe();
    const auto parsed = core::MeasureRegion::parse("ellipse:1,2,3,0,0,2,1,1,0,5,4,2");
    EXPECT_EQ(parsed.kind, core::MeasureRegion::Kind::Ellipse);
    EXPECT_NEAR(glm::length(parsed.axis - glm::dvec3(M_SQRT1_2, M_SQRT1_2, 0)), 0.0, 1e-12);
    EXPECT_DOUBLE_EQ(parsed.radius2, 4.0);
}

// A rectangle dragged corner to corner on a slice is the polygon of its four corners, whichever
// corner the drag starts from; one of no width is refused.
TEST(RegionStatistics, ARectangleIsThePolygonOfItsCorners) {
    const SliceCase c(13);
    const auto& [g, centre] = std::tie(c.g, c.centre);
    const auto& reader = c.reader;
    const double z = centre.z, x0 = g.origin.x + 10.2, x1 = g.origin.x + 26.2, y0 = g.origin.y + 6.2, y1 = g.origin.y + 22.2;
    const auto box = core::RegionStatistics::compute(*reader, core::MeasureRegion::box({x0, y0, z - 0.99}, {x1, y1, z + 0.99}));
    for (const auto& r : {core::MeasureRegion::rectangle({x0, y0, z}, {x1, y1, z}, {0, 0, 1}, {1, 0, 0}, 2.0),
                          core::MeasureRegion::rectangle({x1, y0, z}, {x0, y1, z}, {0, 0, -1}, {0, 1, 0}, 2.0)}) {
        const auto s = core::RegionStatistics::compute(*reader, r);
        EXPECT_EQ(s.voxels, 400u);
        EXPECT_DOUBLE_EQ(s.mean, box.mean);
        EXPECT_NEAR(s.areaMm2, 256.0, 1e-9);
        EXPECT_NE(r.describe().find("rectangle 16 by 16 mm"), std::string::npos) << r.describe();
    }
    EXPECT_THROW(core::RegionStatistics::compute(
                     *reader, core::MeasureRegion::rectangle({x0, y0, z}, {x0, y1, z}, {0, 0, 1}, {1, 0, 0}, 2.0)),
                 core::Error);
}

// CT import gives pixels marked as padding (outside the scanned field) -1024 HU, air: a region
// over them counts them at that value. The figures stay those of the stored voxels, and the
// note says how many sit at exactly -1024 HU and what they may be; a region without any, or a
// CT whose values are not HU, says nothing of it.
TEST(RegionStatistics, VoxelsAtTheCtPaddingValueAreCountedAndNamed) {
    test::TempDir dir;
    auto g = ctGeometry({32, 32, 8}, {1.0, 1.0, 2.0});
    test::DenseVolume v;
    v.dims = g.dims;
    std::uint64_t padded = 0;
    for (std::uint32_t k = 0; k < g.dims[2]; ++k)
        for (std::uint32_t j = 0; j < g.dims[1]; ++j)
            for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
                // outside a circular field of view of radius 14 voxels: padding, stored 0 = -1024 HU
                const bool outside = std::hypot(double(i) - 15.5, double(j) - 15.5) > 14.0;
                v.values.push_back(outside ? 0.0 : 1024.0 + 40.0);
                padded += outside && i >= 24;
            }
    const auto reader = core::OctreeReader::open(build(dir, g, v));
    const glm::dmat4 m = g.indexToPatient();
    // A box over the right-hand columns i >= 24, all rows and slices: tissue and padding.
    const auto edge = core::MeasureRegion::box(glm::dvec3(m * glm::dvec4(23.5, -0.5, -0.5, 1)),
                                               glm::dvec3(m * glm::dvec4(31.5, 31.5, 7.5, 1)));
    const auto s = core::RegionStatistics::compute(*reader, edge);
    expectSame(s, bruteForce(g, v, edge), "box over the field's edge");
    EXPECT_EQ(s.atPaddingValue, padded);
    EXPECT_TRUE(s.exact);
    EXPECT_NE(s.note.find(std::to_string(padded) + " of the voxels are at exactly -1024 HU"), std::string::npos) << s.note;
    EXPECT_NE(s.note.find("padding"), std::string::npos) << s.note;
    // Inside the field: no such voxel, no such note.
    const auto inside = core::MeasureRegion::sphere(glm::dvec3(m * glm::dvec4(15.5, 15.5, 4, 1)), 5.0);
    const auto t = core::RegionStatistics::compute(*reader, inside);
    EXPECT_EQ(t.atPaddingValue, 0u);
    EXPECT_EQ(t.note.find("-1024"), std::string::npos) << t.note;
    // A CT map that is not in HU (RescaleType mg/mL): its values are not HU, nothing is said.
    test::TempDir other;
    g.notHounsfield = true;
    const auto mapReader = core::OctreeReader::open(build(other, g, v));
    const auto u = core::RegionStatistics::compute(*mapReader, edge);
    EXPECT_EQ(u.atPaddingValue, 0u);
    EXPECT_EQ(u.note.find("-1024"), std::string::npos) << u.note;
}
