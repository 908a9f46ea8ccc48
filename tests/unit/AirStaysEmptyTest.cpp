// Air stays empty: bright spheres inside some bricks of an otherwise air-filled volume, seen from
// the six axis views (which look along the edges where four bricks meet) and several oblique
// ones. No pixel whose ray passes far from every sphere may show anything (the thin bright lines
// once drawn along brick edges in air).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "core/reference/CpuRayCaster.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/OctreeScene.h"

using namespace hvx;

namespace {
struct Spheres {
    std::vector<glm::dvec3> centres;  // voxel index space
    double radius = 5.0;
};

test::MemoryVoxelSource airWithSpheres(const Spheres& s) {
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::Int16;
    g.spacing = {1.0, 1.0, 1.0};
    g.modality = "CT";
    test::DenseVolume v;
    v.dims = {96, 96, 96};
    v.values.assign(std::size_t(96 * 96 * 96), -1000.0);
    for (int k = 0; k < 96; ++k)
        for (int j = 0; j < 96; ++j)
            for (int i = 0; i < 96; ++i)
                for (const auto& c : s.centres)
                    if (glm::length(glm::dvec3(i, j, k) - c) <= s.radius) v.values[std::size_t((k * 96 + j) * 96 + i)] = 1000.0;
    return test::MemoryVoxelSource(g, v);
}

/// As the views do: bricks the transfer function hides become empty leaves of the cut.
void cullAsTheViewsDo(test::OctreeScene& scene) {
    core::WorkingSetOptions culled;
    culled.cullByTransferFunction = true;
    scene.ws = std::make_unique<core::WorkingSet>(*scene.reader, *scene.cache, *scene.loader, culled);
}

/// CT bone: air transparent, the spheres (1000 HU) opaque.
core::TransferFunction boneTf(const test::OctreeScene& scene) {
    const auto& g = scene.reader->geometry();
    return core::TransferFunction::preset("ct-bone", g.valueMin, g.valueMax, g.rescaleSlope, g.rescaleIntercept,
                                          scene.ws->space().minSpacing);
}

/// Distance from a point to a ray (origin o, unit direction d), behind the origin included.
double distanceToRay(const glm::dvec3& p, const glm::dvec3& o, const glm::dvec3& d) {
    const glm::dvec3 w = p - o;
    return glm::length(w - glm::dot(w, d) * d);
}
}  // namespace

TEST(AirStaysEmpty, NothingIsDrawnWhereRaysMeetOnlyAir) {
    Spheres s;
    for (double a : {16.0, 80.0})
        for (double b : {16.0, 80.0}) s.centres.push_back({a, b, 48.0});
    s.centres.push_back({48, 48, 16});
    auto src = airWithSpheres(s);
    test::OctreeScene scene(src);
    cullAsTheViewsDo(scene);
    const auto& g = scene.reader->geometry();
    const auto tf = boneTf(scene);
    const glm::dvec3 c = scene.centre();
    struct Dir {
        double az, el;
    };
    for (const Dir& v : {Dir{0, 90}, Dir{0, -90}, Dir{0, 0}, Dir{90, 0}, Dir{180, 0}, Dir{270, 0}, Dir{30, 20}, Dir{-45, 35},
                         Dir{135, -60}}) {
        const auto view = core::View::orbit(c, 260.0, v.az, v.el, 160, 160);
        scene.ws->converge({view}, tf, {}, 32);
        core::RenderSettings rs;
        const auto img = core::CpuRayCaster(*scene.reader, scene.ws->index(), scene.ws->slotData(), tf, rs).render(view);
        std::size_t bad = 0, air = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                glm::dvec3 o, d;
                view.ray(x, y, o, d);
                d = glm::normalize(d);
                double nearest = 1e30;
                for (const auto& sc : s.centres)
                    nearest = std::min(nearest, distanceToRay(glm::dvec3(g.indexToPatient() * glm::dvec4(sc, 1.0)), o, d));
                if (nearest < s.radius + 4.0) continue;  // trilinear support and shading reach a little further
                ++air;
                if (img.rgba[std::size_t(y * img.width + x)].w > 1e-3f) ++bad;
            }
        std::printf("view az %g el %g: %zu of %zu air pixels drawn\n", v.az, v.el, bad, air);
        EXPECT_GT(air, std::size_t(10000));
        EXPECT_EQ(bad, 0u) << "view az " << v.az << " el " << v.el;
    }
}

// The cause of those lines: a ray leaving a leaf through an edge or a corner (several faces at
// once) was given the rope's neighbour with the diagonal neighbour's box, so it sampled a brick
// far outside its own extent. Every visit must lie inside its leaf's own box, for every pixel
// of views that look along the edges where bricks meet.
TEST(AirStaysEmpty, EveryVisitLiesInItsLeafsBox) {
    Spheres s;
    s.centres = {{16, 16, 16}, {80, 80, 80}, {16, 80, 48}, {80, 16, 48}};
    auto src = airWithSpheres(s);
    test::OctreeScene scene(src);
    cullAsTheViewsDo(scene);
    const auto space = scene.ws->space();
    const auto tf = boneTf(scene);
    const int levels = scene.reader->levelCount();
    std::size_t visits = 0, outside = 0;
    for (double el : {90.0, -90.0, 0.0}) {
        const auto view = core::View::orbit(scene.centre(), 260.0, 0.0, el, 200, 200);
        scene.ws->converge({view}, tf, {}, 32);
        const core::CpuRayCaster caster(*scene.reader, scene.ws->index(), scene.ws->slotData(), tf, {});
        for (int y = 0; y < 200; ++y)
            for (int x = 0; x < 200; ++x) {
                glm::dvec3 o, d;
                view.ray(x, y, o, d);
                const glm::dvec3 od(space.patientToOctree * glm::dvec4(o, 1.0));
                const glm::dvec3 dd = glm::dmat3(space.patientToOctree) * d;
                for (const auto& v : caster.traverse(o, d)) {
                    const auto& node = scene.ws->index().nodes[v.node];
                    if (node.z == core::SpatialIndex::kNone) continue;
                    const auto& rn = scene.reader->nodes()[node.z];
                    const double size = std::ldexp(1.0, -(levels - 1 - int(rn.level)));
                    const glm::dvec3 lo = glm::dvec3(rn.x, rn.y, rn.z) * size;
                    const glm::dvec3 mid = od + 0.5 * double(v.tIn + v.tOut) * dd;
                    ++visits;
                    const double slack = 1e-4 * size;
                    bool in = true;
                    for (int a = 0; a < 3; ++a) in = in && mid[a] >= lo[a] - slack && mid[a] <= lo[a] + size + slack;
                    if (!in) ++outside;
                }
            }
    }
    std::printf("%zu leaf visits, %zu outside their leaf's box\n", visits, outside);
    EXPECT_GT(visits, std::size_t(50000));
    EXPECT_EQ(outside, 0u);
}
