#include <gtest/gtest.h>

#include <cstring>

#include <fstream>
#include <numeric>
#include <random>

#include <glm/geometric.hpp>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/reference/CpuRayCaster.h"
#include "core/octree/OctreeBuilder.h"
#include "core/volume/PhantomVoxelSource.h"
#include "core/streaming/SpatialIndexTraversal.h"
#include "core/streaming/WorkingSet.h"
#include "tests/support/DenseMarcher.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/RandomCut.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
std::unique_ptr<core::OctreeReader> buildPhantom(const test::TempDir& dir, std::array<std::uint32_t, 3> dims,
                                                 std::uint32_t brick = 8, double noise = 0.0) {
    core::PhantomVoxelSource p(dims, 3, {400, 400, 400}, noise);
    core::BuildOptions o;
    o.brickSize = brick;
    core::JobContext job;
    core::OctreeBuilder(o).build(p, dir.file("p.hvo"), job);
    return core::OctreeReader::open(dir.file("p.hvo"));
}

core::TransferFunction boneTf(const core::OctreeReader& r) {
    return core::TransferFunction::preset("ct-bone", r.geometry().valueMin, r.geometry().valueMax, 1.0, 0.0, 1.0);
}

core::View frontView(const core::OctreeReader& r, int size, double az = 0.0, double el = 0.0) {
    const auto s = core::OctreeSpace::of(r.geometry(), r.brickSize(), r.levelCount());
    const glm::dvec3 c = s.centre();
    return core::View::orbit(c, 1200.0, az, el, size, size);
}

// Brute force: every index leaf whose box the ray crosses with positive length, by entry.
std::vector<std::uint32_t> bruteForceLeaves(const core::SpatialIndex& idx, const core::OctreeSpace& space,
                                            const glm::dvec3& ow, const glm::dvec3& dw) {
    const glm::dvec3 o(space.patientToOctree * glm::dvec4(ow, 1.0));
    const glm::dvec3 d(glm::dmat3(space.patientToOctree) * dw);
    // The ray is clipped to the volume box first, as the caster does.
    double c0 = 0, c1 = 1e300;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-15) continue;
        double ta = -o[a] / d[a], tb = (space.extent[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        c0 = std::max(c0, ta);
        c1 = std::min(c1, tb);
    }
    std::vector<std::pair<double, std::uint32_t>> hits;
    // Boxes: walk the index top down.
    std::vector<std::tuple<std::uint32_t, glm::dvec3, glm::dvec3>> stack{{0u, glm::dvec3(0), glm::dvec3(1)}};
    while (!stack.empty()) {
        auto [n, lo, hi] = stack.back();
        stack.pop_back();
        double t0 = c0, t1 = c1;
        for (int a = 0; a < 3; ++a) {
            if (std::abs(d[a]) < 1e-15) {
                if (o[a] < lo[a] || o[a] > hi[a]) t1 = -1;
                continue;
            }
            double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
        }
        if (!(t1 - t0 > 1e-4)) continue;
        const auto& nd = idx.nodes[n];
        if (nd.y & core::SpatialIndex::kLeafBit) {
            hits.push_back({t0, n});
            continue;
        }
        const glm::dvec3 mid = 0.5 * (lo + hi);
        for (std::uint32_t oct = 0; oct < 8; ++oct) {
            const glm::dvec3 s((oct & 1) ? 1 : 0, (oct & 2) ? 1 : 0, (oct & 4) ? 1 : 0);
            stack.push_back({nd.x + oct, glm::mix(lo, mid, s), glm::mix(mid, hi, s)});
        }
    }
    std::sort(hits.begin(), hits.end());
    std::vector<std::uint32_t> out;
    for (auto& h : hits) out.push_back(h.second);
    return out;
}
}  // namespace

TEST(SpatialIndexTraversal, VisitsExactlyTheLeavesABruteForceRayBoxTestFindsInOrder) {
    test::TempDir dir;
    const auto r = buildPhantom(dir, {70, 52, 45}, 4);
    const auto space = core::OctreeSpace::of(r->geometry(), r->brickSize(), r->levelCount());
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<std::shared_ptr<const std::vector<float>>> noSlots;
    const auto tf = boneTf(*r);
    std::size_t rays = 0, leaves = 0;
    for (int trial = 0; trial < 20; ++trial) {
        const auto cut = test::randomCut(*r, rng, 0.6);
        std::vector<std::uint32_t> slots(cut.size(), core::SpatialIndex::kNone);
        const auto idx = core::SpatialIndex::build(*r, cut, slots);
        const core::CpuRayCaster caster(*r, idx, noSlots, tf, {});
        for (int k = 0; k < 60; ++k) {
            glm::dvec3 a(space.octreeToPatient * glm::dvec4(u(rng) * space.extent, 1.0));
            glm::dvec3 b(space.octreeToPatient * glm::dvec4(u(rng) * space.extent, 1.0));
            glm::dvec3 origin;
            if (k % 3 == 0) origin = a;                 // starts inside the volume
            else origin = a + glm::normalize(a - b) * 500.0;  // starts outside
            if (k % 5 == 0) {
                // Grazing: aim along a node face or through an edge / corner of the octree grid.
                const double q = 0.25 * double(1 + rng() % 3);
                b = glm::dvec3(space.octreeToPatient * glm::dvec4(q * space.extent.x, q * space.extent.y,
                                                                   u(rng) * space.extent.z, 1.0));
                a = glm::dvec3(space.octreeToPatient * glm::dvec4(q * space.extent.x, q * space.extent.y, 0.0, 1.0));
                origin = a + glm::normalize(a - b) * 300.0;
            }
            const glm::dvec3 rayDir = glm::normalize(b - origin);
            const auto want = bruteForceLeaves(idx, space, origin, rayDir);
            std::vector<std::uint32_t> got;
            for (const auto& v : caster.traverse(origin, rayDir))
                if (v.tOut - v.tIn > 1e-3f) got.push_back(v.node);
            // Leaves crossed for a negligible length may be visited or not; compare the rest.
            std::vector<std::uint32_t> wantLong;
            for (auto n : want) wantLong.push_back(n);
            std::vector<std::uint32_t> gotFiltered;
            for (auto n : got)
                if (std::find(want.begin(), want.end(), n) != want.end()) gotFiltered.push_back(n);
            EXPECT_EQ(gotFiltered.size(), got.size()) << "traversal visited a leaf the ray does not cross";
            std::vector<std::uint32_t> wantVisited;
            for (auto n : want)
                if (std::find(got.begin(), got.end(), n) != got.end()) wantVisited.push_back(n);
            EXPECT_EQ(gotFiltered, wantVisited) << "order differs, trial " << trial << " ray " << k;
            EXPECT_GE(got.size() + 1, want.size()) << "skipped leaves, trial " << trial << " ray " << k;
            ++rays;
            leaves += got.size();
        }
    }
    EXPECT_GT(leaves, rays);  // rays really cross several leaves
}

// Rays nearly parallel to a node face (a millionth of a radian off it, as a light-field
// display's compressed depth makes them): the nudge past an exit face moved the point too little
// along the face's axis to leave the leaf, the same leaf was found again and the ray ended
// there (dark lines along brick faces in Looking Glass quilts). Each such ray must reach the
// volume's far side through every leaf it crosses.
TEST(CpuRayCaster, RaysGrazingANodeFaceReachTheFarSide) {
    test::TempDir dir;
    const auto r = buildPhantom(dir, {64, 64, 64}, 8);
    const auto space = core::OctreeSpace::of(r->geometry(), r->brickSize(), r->levelCount());
    std::mt19937 rng(5);
    const auto cut = test::randomCut(*r, rng, 1.0);  // full resolution everywhere
    std::vector<std::uint32_t> slots(cut.size(), core::SpatialIndex::kNone);
    const auto idx = core::SpatialIndex::build(*r, cut, slots);
    std::vector<std::shared_ptr<const std::vector<float>>> noSlots;
    const core::CpuRayCaster caster(*r, idx, noSlots, boneTf(*r), {});
    int stopped = 0, rays = 0;
    for (const double q : {0.25, 0.5, 0.75})
        for (const double sign : {-1.0, 1.0})
            for (const double tilt : {1e-6, 1e-5, 3e-7}) {
                // Along +y, crossing the plane x = q (octree units) inside the volume, at a grazing
                // angle of `tilt`.
                const double x = q * space.extent.x;
                const glm::dvec3 from(space.octreeToPatient * glm::dvec4(x - sign * 0.6 * tilt, -0.2, 0.37 * space.extent.z, 1.0));
                const glm::dvec3 to(space.octreeToPatient * glm::dvec4(x + sign * 0.4 * tilt, 1.2, 0.37 * space.extent.z, 1.0));
                const glm::dvec3 dirW = glm::normalize(to - from);
                const auto want = bruteForceLeaves(idx, space, from, dirW);
                const auto visits = caster.traverse(from, dirW);
                ++rays;
                if (want.empty()) continue;
                const bool reached = !visits.empty() && std::find_if(visits.begin(), visits.end(), [&](const auto& v) {
                                                            return v.node == want.back();
                                                        }) != visits.end();
                stopped += reached ? 0 : 1;
                EXPECT_TRUE(reached) << "x = " << q << " tilt " << sign * tilt << ": " << visits.size() << " of "
                                     << want.size() << " leaves visited";
            }
    EXPECT_EQ(stopped, 0) << "of " << rays << " grazing rays";
}

TEST(CpuRayCaster, FullResolutionCutMatchesDenseRayMarching) {
    // Dense reference: march the full-resolution volume with the same step and compositing.
    test::TempDir dir;
    const auto r = buildPhantom(dir, {48, 40, 36}, 8);
    core::PhantomVoxelSource dense({48, 40, 36}, 3, {400, 400, 400}, 0.0);
    const auto tf = core::TransferFunction::preset("ct-soft-tissue", r->geometry().valueMin, r->geometry().valueMax,
                                                   1.0, 0.0, 8.0);
    core::BrickCache cache(1u << 30);
    core::BrickLoader loader(*r, cache);
    core::WorkingSetOptions opt;
    opt.voxelsPerPixel = 1e-6;  // force full resolution
    core::WorkingSet ws(*r, cache, loader, opt);
    const auto view = frontView(*r, 64, 25, 10);
    ws.converge({view}, tf);
    core::RenderSettings rs;
    rs.shading = false;
    const core::CpuRayCaster caster(*r, ws.index(), ws.slotData(), tf, rs);
    const auto img = caster.render(view);
    // Brute force on the dense volume: the test's own trilinear sampling in voxel index space.
    const test::DenseMarcher marcher(dense, r->geometry());
    double maxDiff = 0, sumDiff = 0;
    int covered = 0, large = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            glm::dvec3 o, d, oi, di;
            view.ray(x, y, o, d);
            double t0 = 0, t1 = 0;
            marcher.clip(o, d, oi, di, t0, t1);
            glm::dvec3 c(0);
            double alpha = 0;
            if (t1 > t0) {
                const double dt = 1.0 / glm::length(di) * 1.0;  // one voxel
                double sPrev = marcher.value(oi + t0 * di);
                for (double t = t0 + dt; t <= t1 && alpha < 0.99; t += dt) {
                    const double s = marcher.value(oi + t * di);
                    const glm::dvec4 f = tf.segment(sPrev, s);
                    const double a = 1 - std::exp(-f.w * dt);
                    if (a > 1e-6) {
                        c += (1 - alpha) * a * glm::dvec3(f) / f.w;
                        alpha += (1 - alpha) * a;
                    }
                    sPrev = s;
                }
            }
            const glm::vec4 got = img.rgba[std::size_t(y) * 64 + std::size_t(x)];
            const double diff = std::abs(double(got.a) - alpha) + glm::length(glm::dvec3(got) - c);
            maxDiff = std::max(maxDiff, diff);
            sumDiff += diff;
            large += diff > 0.1;
            if (diff > 0.1 && large <= 3)
                std::printf("  pixel %d,%d: got rgb %.3f %.3f %.3f a %.3f, dense rgb %.3f %.3f %.3f a %.3f\n", x, y, got.r,
                            got.g, got.b, got.a, c.r, c.g, c.b, alpha);
            covered += alpha > 0.05;
        }
    const double meanDiff = sumDiff / (64 * 64);
    std::printf("CPU reference vs dense marching: mean |diff| %.4f, max %.4f, %d of %d covered pixels off by > 0.1\n",
                meanDiff, maxDiff, large, covered);
    EXPECT_GT(covered, 500);
    EXPECT_LT(meanDiff, 0.002);
    // Samples restart at brick faces, so a sharp surface can be met one sample earlier or later:
    // only a few silhouette pixels may differ noticeably.
    EXPECT_LT(large, covered / 200);
}

TEST(CpuRayCaster, SkippingCellsThatCannotShowChangesNothing) {
    // Without culling, rays cross bricks that are mostly transparent; stepping over their empty
    // cells (2- and 8-voxel cells here) must give the image of sampling them, in DVR and for
    // the isosurface's first hit.
    for (std::uint32_t brickSize : {8u, 32u}) {
        test::TempDir dir;
        const auto r = buildPhantom(dir, {96, 96, 80}, brickSize);
        const auto& g = r->geometry();
        core::BrickCache cache(1u << 30);
        core::BrickLoader loader(*r, cache);
        core::WorkingSetOptions opt;
        opt.cullByTransferFunction = false;
        core::WorkingSet ws(*r, cache, loader, opt);
        const auto view = frontView(*r, 72, 25, 10);
        const auto bone = core::TransferFunction::preset("ct-bone", g.valueMin, g.valueMax, 1.0, 0.0, 4.0);
        ws.converge({view}, bone);
        for (const char* preset : {"ct-bone", "ct-soft-tissue", "iso"}) {
            const bool iso = !std::strcmp(preset, "iso");
            const auto tf = iso ? bone : core::TransferFunction::preset(preset, g.valueMin, g.valueMax, 1.0, 0.0, 4.0);
            core::RenderSettings rs;
            if (iso) {
                rs.mode = core::RenderSettings::Mode::Iso;
                rs.isoValue = 300;
            }
            const auto skipped = core::CpuRayCaster(*r, ws.index(), ws.slotData(), tf, rs).render(view);
            rs.skipEmptyCells = false;
            const auto dense = core::CpuRayCaster(*r, ws.index(), ws.slotData(), tf, rs).render(view);
            double maxDiff = 0, coverage = 0;
            for (std::size_t i = 0; i < dense.rgba.size(); ++i) {
                const glm::vec4 d = glm::abs(skipped.rgba[i] - dense.rgba[i]);
                maxDiff = std::max(maxDiff, double(std::max(std::max(d.r, d.g), std::max(d.b, d.a))));
                coverage += dense.rgba[i].a;
            }
            EXPECT_GT(coverage / double(dense.rgba.size()), 0.05) << preset;
            // A jump lands on t + (k - 2)·dt, not on the sum of k - 2 steps: the float grid moves
            // by rounding, and the isosurface's bisection and normal follow it by as much.
            EXPECT_LT(maxDiff, iso ? 1e-2 : 1e-3) << preset << ", bricks of " << brickSize;
        }
    }
}

TEST(WorkingSet, RefinementRespectsBudgetCullingAndConvergesToTheAccuracyTarget) {
    test::TempDir dir;
    const auto r = buildPhantom(dir, {96, 96, 80}, 8);
    const auto tf = boneTf(*r);
    core::BrickCache cache(1u << 30);
    core::BrickLoader loader(*r, cache);
    core::WorkingSetOptions opt;
    opt.maxBricks = 40;
    opt.clip = true;
    opt.clipPlane = glm::dvec4(0, 0, 1, 0);  // keep the superior half (z >= 0)
    core::WorkingSet ws(*r, cache, loader, opt);
    auto view = frontView(*r, 256, 0, 0);
    view.fovYDegrees = 12;  // the volume overflows the frustum: some nodes are off screen
    ws.converge({view}, tf);
    EXPECT_LE(ws.stats().cutNodes, 40u);
    const auto clip = view.viewProjection();
    const auto& space = ws.space();
    for (auto id : ws.cut()) {
        const auto& n = r->nodes()[id];
        EXPECT_FALSE(tf.isEmpty(n.minValue, n.maxValue)) << "empty node " << id << " in the cut";
        const int depth = r->levelCount() - 1 - n.level;
        const double size = std::ldexp(1.0, -depth);
        bool kept = false;
        // Off screen for certain when all eight corners lie beyond one side of the frustum.
        int beyond[4] = {0, 0, 0, 0};  // left, right, bottom, top
        for (int c = 0; c < 8; ++c) {
            glm::dvec3 p = glm::dvec3(n.x + (c & 1), n.y + ((c >> 1) & 1), n.z + ((c >> 2) & 1)) * size;
            p = glm::min(p, space.extent);
            const glm::dvec3 w(space.octreeToPatient * glm::dvec4(p, 1));
            kept = kept || w.z >= 0;
            const glm::dvec4 q = clip * glm::dvec4(w, 1);
            beyond[0] += q.x < -q.w;
            beyond[1] += q.x > q.w;
            beyond[2] += q.y < -q.w;
            beyond[3] += q.y > q.w;
        }
        EXPECT_TRUE(kept) << "clipped node " << id << " in the cut";
        for (int side = 0; side < 4; ++side) EXPECT_LT(beyond[side], 8) << "node " << id << " is off screen";
    }
    // Unlimited budget, a small image: every cut node meets the target, or has full resolution.
    opt.maxBricks = 100000;
    opt.clip = false;
    const auto small = frontView(*r, 40, 20, 10);
    core::WorkingSet full(*r, cache, loader, opt);
    full.converge({small}, tf);
    EXPECT_TRUE(full.stats().complete);
    std::size_t coarser = 0;
    for (auto id : full.cut()) {
        const auto& n = r->nodes()[id];
        if (n.level == 0) continue;
        ++coarser;
        const double voxel = space.voxelSize(n.level);
        const glm::dvec3 centre(space.octreeToPatient *
                                glm::dvec4((glm::dvec3(n.x, n.y, n.z) + 0.5) * std::ldexp(1.0, -(r->levelCount() - 1 - n.level)), 1));
        EXPECT_LE(voxel, small.pixelFootprint(centre) + 1e-9) << "node " << id << " is coarser than a pixel";
    }
    EXPECT_GT(coarser, 0u);
    // Coarser accuracy needs fewer bricks.
    opt.voxelsPerPixel = 4.0;
    core::WorkingSet coarse(*r, cache, loader, opt);
    coarse.converge({small}, tf);
    EXPECT_LT(coarse.stats().cutNodes, full.stats().cutNodes);
}

TEST(WorkingSet, VisibilityFeedbackStopsRefiningWhatNoRaySees) {
    test::TempDir dir;
    const auto r = buildPhantom(dir, {96, 96, 64}, 8);
    const auto tf = core::TransferFunction::preset("ct-soft-tissue", r->geometry().valueMin, r->geometry().valueMax,
                                                   1.0, 0.0, 1.0);
    core::BrickCache cache(1u << 30);
    core::BrickLoader loader(*r, cache);
    core::WorkingSetOptions opt;
    opt.voxelsPerPixel = 0.25;
    core::WorkingSet ws(*r, cache, loader, opt);
    const auto view = frontView(*r, 128);
    ws.converge({view}, tf);
    const std::size_t before = ws.stats().cutNodes;
    core::RenderSettings rs;
    rs.countRays = true;
    const auto img = core::CpuRayCaster(*r, ws.index(), ws.slotData(), tf, rs).render(view);
    ws.setRayCounts(img.rayCounts);
    ws.converge({view}, tf);
    std::printf("working set with an opaque-ish TF: %zu bricks, %zu after visibility feedback\n", before,
                ws.stats().cutNodes);
    EXPECT_LT(ws.stats().cutNodes, before) << "feedback must stop refining something no ray reaches";
    // What no ray reached is not drawn either: the image is the same.
    const auto after = core::CpuRayCaster(*r, ws.index(), ws.slotData(), tf, rs).render(view);
    double worst = 0;
    for (std::size_t i = 0; i < img.rgba.size(); ++i)
        worst = std::max(worst, double(glm::length(img.rgba[i] - after.rgba[i])));
    EXPECT_LT(worst, 1e-4) << "visibility feedback changed what is seen";
}

TEST(BrickLoader, BudgetsCancellationStaleRequestsAndCorruptBricks) {
    test::TempDir dir;
    const auto r = buildPhantom(dir, {64, 64, 64}, 8, 10.0);
    const std::size_t brickBytes = std::size_t(r->brickEdge()) * r->brickEdge() * r->brickEdge() * 2;
    core::BrickCache cache(brickBytes * 10);
    {
        core::BrickLoader loader(*r, cache, 2);
        std::vector<std::uint32_t> all(r->nodes().size());
        std::iota(all.begin(), all.end(), 0u);
        loader.loadNow(all);
        EXPECT_LE(cache.bytes(), cache.budget());
        EXPECT_EQ(cache.count(), 10u);
    }
    core::BrickCache big(1u << 30);
    {
        core::BrickLoader loader(*r, big, 1);
        for (std::uint32_t n = 0; n < r->nodes().size(); ++n) loader.request(n, double(n));
        loader.cancelAll();
        EXPECT_EQ(loader.queued(), 0u);
        EXPECT_GT(loader.droppedCount(), 0u);
    }
    {
        core::BrickLoader loader(*r, big, 1);
        loader.beginFrame();
        for (std::uint32_t n = 0; n < r->nodes().size(); ++n) loader.request(n, 1.0);
        loader.beginFrame();
        loader.beginFrame();  // not renewed for a frame: stale
        EXPECT_EQ(loader.queued(), 0u);
        loader.waitIdle();
        EXPECT_GT(loader.droppedCount(), 0u);
    }
    // A flipped payload byte: the loader reports the node and never caches it; the working set
    // draws the parent instead.
    std::uint32_t victim = 0;
    for (std::uint32_t n = 0; n < r->nodes().size(); ++n)
        if (r->nodes()[n].level == 0 && r->nodes()[n].payloadSize > 0) victim = n;
    {
        std::fstream f(dir.file("p.hvo"), std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(r->nodes()[victim].payloadOffset + 5));
        f.put('\x5a');
    }
    const auto damaged = core::OctreeReader::open(dir.file("p.hvo"));
    core::BrickCache c2(1u << 30);
    core::BrickLoader loader(*damaged, c2, 1);
    loader.loadNow({victim});
    EXPECT_TRUE(loader.failed(victim));
    EXPECT_FALSE(c2.contains(victim));
    ASSERT_FALSE(loader.errors().empty());
    EXPECT_NE(loader.errors()[0].find("node " + std::to_string(victim)), std::string::npos) << loader.errors()[0];
}

TEST(CpuRayCaster, AnteriorViewShowsThePatientsLeftOnTheImageRight) {
    // The phantom's contrast-filled heart lies on the patient's left (+x in LPS).
    test::TempDir dir;
    const auto r = buildPhantom(dir, {96, 96, 96}, 8);
    const auto tf = core::TransferFunction::preset("ct-angio", r->geometry().valueMin, r->geometry().valueMax, 1.0,
                                                   0.0, 2.0);
    core::BrickCache cache(1u << 30);
    core::BrickLoader loader(*r, cache);
    core::WorkingSet ws(*r, cache, loader, {});
    const auto view = frontView(*r, 96);
    ws.converge({view}, tf);
    const auto img = core::CpuRayCaster(*r, ws.index(), ws.slotData(), tf, {}).render(view);
    // The heart spans image columns ~45-59 in rows ~34-48; compare it with its mirror image.
    double left = 0, right = 0;
    for (int y = 34; y < 48; ++y)
        for (int x = 0; x < 96; ++x) {
            const double v = img.rgba[std::size_t(y) * 96 + std::size_t(x)].a;
            if (x >= 34 && x < 46) left += v;
            if (x >= 50 && x < 62) right += v;
        }
    EXPECT_GT(right, left * 1.02) << "heart (patient's left) must be on the image right";
}
