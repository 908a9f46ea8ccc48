// A second volume and a label map laid over a slice: markers placed at known patient points
// land where they belong on a rotated, anisotropic partner grid; labels are never blended into
// a colour that no label has; partners in another frame of reference are refused.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include "core/octree/OctreeBuilder.h"
#include "core/reference/SliceComposer.h"
#include "core/reference/SliceSampler.h"
#include "core/volume/FramePairing.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
const glm::dvec3 kMarkers[2] = {{5.3, -7.1, 9.4}, {-12.2, 10.6, -4.8}};

/// A float volume centred on the LPS origin whose value at each voxel is the sum of Gaussian
/// blobs (sigma mm) at the markers, computed from the voxel's own patient position.
std::unique_ptr<core::OctreeReader> markerVolume(const test::TempDir& dir, const std::string& name,
                                                 std::array<std::uint32_t, 3> dims, glm::dvec3 spacing,
                                                 glm::dmat3 direction, double sigma, std::string frame = "1.2.3.4") {
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::Float32;
    g.spacing = spacing;
    g.direction = direction;
    g.origin = -(direction * ((glm::dvec3(dims[0], dims[1], dims[2]) - 1.0) * spacing / 2.0));
    g.frameOfReferenceUid = std::move(frame);
    g.dims = dims;
    test::DenseVolume v;
    v.dims = dims;
    for (std::uint32_t k = 0; k < dims[2]; ++k)
        for (std::uint32_t j = 0; j < dims[1]; ++j)
            for (std::uint32_t i = 0; i < dims[0]; ++i) {
                const glm::dvec3 p(g.indexToPatient() * glm::dvec4(i, j, k, 1.0));
                double s = 0;
                for (const auto& m : kMarkers) s += 1000 * std::exp(-glm::dot(p - m, p - m) / (2 * sigma * sigma));
                v.values.push_back(s);
            }
    test::MemoryVoxelSource source(g, v);
    core::BuildOptions o;
    o.brickSize = 16;
    core::JobContext job;
    core::OctreeBuilder(o).build(source, dir.file(name), job);
    return core::OctreeReader::open(dir.file(name));
}

/// The patient position of the brightest part of a slice: the value-weighted centroid of the
/// pixels above half the maximum.
glm::dvec3 peak(const core::SliceImage& s, const core::SlicePlane& plane) {
    float top = 0;
    for (float v : s.values)
        if (!std::isnan(v)) top = std::max(top, v);
    glm::dvec2 sum(0);
    double w = 0;
    for (int j = 0; j < s.height; ++j)
        for (int i = 0; i < s.width; ++i) {
            const float v = s.values[std::size_t(j) * std::size_t(s.width) + std::size_t(i)];
            if (std::isnan(v) || v < top / 2) continue;
            sum += double(v) * glm::dvec2(i + 0.5, j + 0.5);
            w += v;
        }
    const glm::dvec2 px = sum / w;
    return plane.centre + (px.x - plane.width / 2.0) * plane.pixelMm * plane.right +
           (px.y - plane.height / 2.0) * plane.pixelMm * plane.down;
}
}  // namespace

TEST(SliceLayers, MarkersCoincideOnARotatedAnisotropicPartner) {
    test::TempDir dir;
    const auto base = markerVolume(dir, "base.hvo", {64, 64, 64}, {1, 1, 1}, glm::dmat3(1.0), 2.5);
    // The partner: 30° about an oblique axis, spacings 0.7 × 1.3 × 2.1 mm.
    const glm::dmat3 rot(glm::rotate(glm::dmat4(1.0), glm::radians(30.0), glm::normalize(glm::dvec3(1, 2, 0.5))));
    const auto partner = markerVolume(dir, "partner.hvo", {70, 40, 26}, {0.7, 1.3, 2.1}, rot, 3.5);
    EXPECT_TRUE(core::FramePairing::of(base->geometry(), "base", partner->geometry(), "partner").sentence.empty());
    core::BrickCache cache(64u << 20), cache2(64u << 20);
    const core::SliceSampler a(*base, cache), b(*partner, cache2);
    int planes = 0;
    for (const auto& m : kMarkers)
        for (const auto& plane :
             {core::SlicePlane::standard(core::SlicePlane::Orientation::Axial, m + glm::dvec3(3, -2, 0), 0.5, 96, 96),
              core::SlicePlane::standard(core::SlicePlane::Orientation::Sagittal, m + glm::dvec3(0, 4, 1), 0.5, 96, 96),
              core::SlicePlane::oblique({0.3, -0.2, 1}, m + glm::dvec3(1, 1, 0), 0.5, 96, 96)}) {
            const auto pa = peak(a.sample(plane, 0), plane), pb = peak(b.sample(plane, 0), plane);
            // Where the marker crosses the plane: its foot on the plane.
            const glm::dvec3 foot = m - glm::dot(m - plane.centre, plane.normal()) * plane.normal();
            EXPECT_LT(glm::length(pa - foot), 0.25) << "base, plane " << planes;
            EXPECT_LT(glm::length(pb - foot), 0.25) << "partner, plane " << planes;
            EXPECT_LT(glm::length(pa - pb) / plane.pixelMm, 0.5) << "pixels apart, plane " << planes;
            ++planes;
        }
    EXPECT_EQ(planes, 6);
}

TEST(SliceLayers, FusedSliceShowsTheOverlayOnlyWhereItRisesAboveItsWindow) {
    test::TempDir dir;
    const auto base = markerVolume(dir, "base.hvo", {32, 32, 32}, {2, 2, 2}, glm::dmat3(1.0), 2.5);
    const auto over = markerVolume(dir, "over.hvo", {32, 32, 32}, {2, 2, 2}, glm::dmat3(1.0), 4.0);
    core::BrickCache c1(16u << 20), c2(16u << 20);
    const auto plane = core::SlicePlane::standard(core::SlicePlane::Orientation::Axial, kMarkers[0], 1.0, 64, 64);
    const auto bi = core::SliceSampler(*base, c1).sample(plane), oi = core::SliceSampler(*over, c2).sample(plane);
    const core::DisplayWindow w{"", 500, 1000};
    core::SliceOverlay o{&oi, &over->geometry(), core::ColorMap::named("hot"), {"", 600, 800}, 1.0};
    const auto rgb = core::SliceComposer::compose(bi, base->geometry(), w, &o, nullptr);
    const auto grey = core::SliceComposer::grey(bi, base->geometry(), w);
    int coloured = 0, plain = 0;
    for (std::size_t i = 0; i < grey.size(); ++i) {
        const double t = (oi.values[i] - 200.0) / 800.0;
        const std::array<std::uint8_t, 3> got{rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]};
        if (std::lround(std::min(t, 1.0) * 255) <= 0) {  // the map's first entry: the base untouched
            EXPECT_EQ(got, (std::array<std::uint8_t, 3>{grey[i], grey[i], grey[i]})) << i;
            ++plain;
        } else {  // opacity 1: the map's colour itself
            EXPECT_EQ(got, o.map.at(t)) << i;
            ++coloured;
        }
    }
    EXPECT_GT(coloured, 20);
    EXPECT_GT(plain, 2000);
}

TEST(SliceLayers, LabelsKeepTheirOwnColoursAtEveryPixel) {
    test::TempDir dir;
    // Blocks of 3 voxels alternate labels 1, 2 and 0: trilinear sampling would make 1.5 and
    // 0.7 at every boundary; a label must be the nearest voxel's.
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::UInt8;
    g.isLabel = true;
    g.spacing = {0.9, 1.1, 1.6};
    g.origin = {-20, -25, -30};
    test::DenseVolume v;
    v.dims = {40, 40, 30};
    for (std::uint32_t k = 0; k < 30; ++k)
        for (std::uint32_t j = 0; j < 40; ++j)
            for (std::uint32_t i = 0; i < 40; ++i) v.values.push_back(double((i / 3 + j / 3 + k / 3) % 3));
    {
        test::MemoryVoxelSource source(g, v);
        core::BuildOptions o;
        o.brickSize = 16;
        o.labels = true;
        core::JobContext job;
        core::OctreeBuilder(o).build(source, dir.file("labels.hvo"), job);
    }
    const auto reader = core::OctreeReader::open(dir.file("labels.hvo"));
    ASSERT_TRUE(reader->geometry().isLabel);
    core::BrickCache cache(16u << 20);
    const core::SliceSampler sampler(*reader, cache);
    const auto table = core::LabelTable::generated({1, 2});
    const glm::dmat4 toIndex = glm::inverse(reader->geometry().indexToPatient());
    std::size_t checked = 0;
    for (const auto& plane :
         {core::SlicePlane::oblique({0.4, 0.3, 1}, {0.37, -1.21, 2.03}, 0.31, 120, 110),
          core::SlicePlane::standard(core::SlicePlane::Orientation::Coronal, {1.1, 0.45, -3.3}, 0.43, 100, 80)}) {
        const auto img = sampler.sample(plane, 0);
        const core::SliceLabels layer{&img, &table, 1.0, true, false};
        const auto rgb = core::SliceComposer::compose(img, reader->geometry(), {"", 1, 2}, nullptr, &layer);
        for (int j = 0; j < img.height; ++j)
            for (int i = 0; i < img.width; ++i) {
                const std::size_t n = std::size_t(j) * std::size_t(img.width) + std::size_t(i);
                const float got = img.values[n];
                if (std::isnan(got)) continue;
                // The nearest voxel, found here from the geometry alone (ties skipped).
                const glm::dvec3 p = plane.centre + (i + 0.5 - plane.width / 2.0) * plane.pixelMm * plane.right +
                                     (j + 0.5 - plane.height / 2.0) * plane.pixelMm * plane.down;
                const glm::dvec3 idx(toIndex * glm::dvec4(p, 1.0));
                const glm::dvec3 r = glm::round(idx);
                if (glm::any(glm::lessThan(glm::abs(glm::abs(idx - r) - 0.5), glm::dvec3(1e-6)))) continue;
                const auto want = v.clamped(long(r.x), long(r.y), long(r.z));
                ASSERT_EQ(double(got), want) << "pixel " << i << "," << j;
                const std::array<std::uint8_t, 3> colour{rgb[3 * n], rgb[3 * n + 1], rgb[3 * n + 2]};
                if (want == 0) EXPECT_EQ(colour[0], colour[1]);  // the base's grey
                else {
                    const auto& c = table.find(int(want))->rgba;
                    EXPECT_EQ(colour, (std::array<std::uint8_t, 3>{c[0], c[1], c[2]})) << "pixel " << i << "," << j;
                }
                ++checked;
            }
    }
    EXPECT_GT(checked, 15000u);
    // A slab of a label map is refused: it would make up classes.
    EXPECT_THROW(sampler.sampleSlab(core::SlicePlane{}, 5.0, core::SlabMode::Mean), core::Error);
}

TEST(SliceLayers, OutlinesMarkEachLabelsBorderAtItsOwnColour) {
    core::SliceImage s;
    s.width = 6, s.height = 5;
    s.values.assign(30, 0.f);
    for (int j = 1; j < 4; ++j)
        for (int i = 1; i < 5; ++i) s.values[std::size_t(j * 6 + i)] = 4.f;  // a 4×3 block of label 4
    const auto table = core::LabelTable::generated({4});
    const core::SliceLabels outline{&s, &table, 0.0, false, true};
    core::VolumeGeometry g;
    const auto rgb = core::SliceComposer::compose(s, g, {"", 10, 20}, nullptr, &outline);
    const auto& c = table.find(4)->rgba;
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 6; ++i) {
            const std::size_t n = std::size_t(j * 6 + i);
            const bool inside = i >= 1 && i <= 4 && j >= 1 && j <= 3;
            const bool border = inside && (i == 1 || i == 4 || j == 1 || j == 3);
            const bool drawn = rgb[3 * n] == c[0] && rgb[3 * n + 1] == c[1] && rgb[3 * n + 2] == c[2];
            EXPECT_EQ(drawn, border) << i << "," << j;
        }
}

TEST(SliceLayers, PartnersInAnotherFrameOrWithoutOrientationAreRefused) {
    core::VolumeGeometry a, b;
    a.frameOfReferenceUid = "1.2.3";
    b.frameOfReferenceUid = "1.2.4";
    const auto other = core::FramePairing::of(a, "ct.hvo", b, "pet.hvo");
    EXPECT_TRUE(other.refused);
    EXPECT_NE(other.sentence.find("different frames of reference (1.2.3 and 1.2.4)"), std::string::npos) << other.sentence;
    b.frameOfReferenceUid = "1.2.3";
    EXPECT_FALSE(core::FramePairing::of(a, "ct.hvo", b, "pet.hvo").refused);
    b.frameOfReferenceUid.clear();
    const auto unknown = core::FramePairing::of(a, "ct.hvo", b, "atlas.hvo");
    EXPECT_FALSE(unknown.refused);
    EXPECT_NE(unknown.sentence.find("frame of reference of atlas.hvo is not known"), std::string::npos);
    b.orientationAssumed = true;
    const auto assumed = core::FramePairing::of(a, "ct.hvo", b, "atlas.hvo");
    EXPECT_TRUE(assumed.refused);
    EXPECT_NE(assumed.sentence.find("atlas.hvo has no known orientation"), std::string::npos);
}

TEST(SliceLayers, TheFrameOfReferenceTravelsInTheOctree) {
    test::TempDir dir;
    const std::string uid64(64, '7');  // the longest a UID may be fills the field exactly
    for (const std::string& uid : {std::string("1.2.840.113619.2.55.3"), uid64, std::string()}) {
        const auto r = markerVolume(dir, "f.hvo", {8, 8, 8}, {1, 1, 1}, glm::dmat3(1.0), 2.0, uid);
        EXPECT_EQ(r->geometry().frameOfReferenceUid, uid);
    }
}
