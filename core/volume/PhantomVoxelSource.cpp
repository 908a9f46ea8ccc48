#include "core/volume/PhantomVoxelSource.h"

#include <algorithm>
#include <cmath>

#include "core/base/ThreadPool.h"

namespace hvx::core {

namespace {
constexpr double kAir = -1000.0;

std::uint64_t mix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

double sq(double x) { return x * x; }

// Ellipsoid "radius" (< 1 inside).
double ell(double u, double v, double w, double cu, double cv, double cw, double ru, double rv, double rw) {
    return sq((u - cu) / ru) + sq((v - cv) / rv) + sq((w - cw) / rw);
}
}  // namespace

PhantomVoxelSource::PhantomVoxelSource(std::array<std::uint32_t, 3> dims, std::uint64_t seed,
                                       glm::dvec3 fieldOfViewMm, double noiseHu)
    : seed_(seed), noiseHu_(noiseHu) {
    geometry_.dims = dims;
    geometry_.scalarType = ScalarType::Int16;
    geometry_.modality = "CT";
    for (int a = 0; a < 3; ++a) {
        geometry_.spacing[a] = fieldOfViewMm[a] / std::max<std::uint32_t>(1, dims[a]);
        geometry_.origin[a] = -0.5 * fieldOfViewMm[a] + 0.5 * geometry_.spacing[a];
    }
    geometry_.valueMin = -1024;
    geometry_.valueMax = 3071;
    geometry_.validate("phantom");
    for (int p = 0; p < 4; ++p) vesselPhase_[p] = double(mix(seed * 31 + std::uint64_t(p)) % 6283) / 1000.0;
}

std::string PhantomVoxelSource::describe() const {
    return "phantom " + std::to_string(geometry_.dims[0]) + "x" + std::to_string(geometry_.dims[1]) + "x" +
           std::to_string(geometry_.dims[2]) + " seed " + std::to_string(seed_);
}

// u: -1 patient right .. +1 patient left; v: -1 anterior .. +1 posterior; w: -1 inferior .. +1 superior.
double PhantomVoxelSource::tissueAt(double u, double v, double w) const {
    const double bodyA = 0.82 * (1.0 - 0.08 * w * w), bodyB = 0.56 * (1.0 - 0.05 * w * w);
    const double body = sq(u / bodyA) + sq((v - 0.04) / bodyB);
    if (body >= 1.0) return kAir;
    if (body > 0.86) return -100.0;  // subcutaneous fat

    // Spine: vertebral bodies separated by discs, cortical shell, canal and posterior arch.
    const double spineR = std::sqrt(sq(u) + sq(v - 0.36));
    const double phase = std::fmod(w * 8.0 + 8.0, 1.0);
    const bool disc = phase > 0.82;
    if (spineR < 0.085) {
        if (disc) return 90.0;
        return spineR > 0.068 || phase < 0.05 || phase > 0.77 ? 900.0 : 260.0;
    }
    const double canalR = std::sqrt(sq(u) + sq(v - 0.49));
    if (canalR < 0.035) return 15.0;
    if (canalR < 0.06 && !disc) return 750.0;

    // Ribs: thin elliptic rings, periodic in w, over the thorax only.
    if (w > -0.25 && w < 0.92 && v < 0.42) {
        const double ring = std::sqrt(sq(u / (bodyA * 0.9)) + sq((v - 0.04) / (bodyB * 0.88)));
        const double ribPhase = std::fmod((w + 0.25) * 9.0, 1.0);
        if (std::abs(ring - 1.0) < 0.035 && ribPhase < 0.32) return std::abs(ring - 1.0) > 0.02 ? 850.0 : 350.0;
    }

    // Aorta (contrast) just left-anterior of the spine.
    if (sq(u - 0.07) + sq(v - 0.2) < sq(0.045)) return 320.0;

    // Lungs with contrast-filled pulmonary vessels.
    for (int side = -1; side <= 1; side += 2) {
        const double lung = ell(u, v, w, side * 0.36, 0.02, 0.42, 0.27, 0.33, 0.52);
        if (lung < 1.0) {
            for (int p = 0; p < 2; ++p) {
                const double ph = vesselPhase_[p + (side > 0 ? 2 : 0)];
                const double cu = side * (0.30 + 0.08 * std::sin(5.0 * w + ph));
                const double cv = 0.02 + 0.12 * std::cos(4.0 * w + ph) * (p ? 1.0 : -1.0);
                if (sq(u - cu) + sq(v - cv) < sq(0.018)) return 180.0;
            }
            return -860.0;
        }
    }

    // Heart on the patient's left (+u), contrast-filled ventricles.
    const double heart = ell(u, v, w, 0.13, -0.14, 0.22, 0.24, 0.19, 0.24);
    if (heart < 1.0) return heart < 0.45 ? 260.0 : 55.0;
    // Liver on the patient's right (-u), below the heart.
    if (ell(u, v, w, -0.3, 0.0, -0.48, 0.38, 0.32, 0.32) < 1.0) return 62.0;
    // Kidneys, contrast-enhanced cortex around a darker medulla.
    for (int side = -1; side <= 1; side += 2) {
        const double k = ell(u, v, w, side * 0.3, 0.3, -0.62, 0.1, 0.08, 0.16);
        if (k < 1.0) return k > 0.5 ? 170.0 : 40.0;
    }
    // Soft tissue with gentle low-frequency texture.
    return 38.0 + 8.0 * std::sin(7.0 * u) * std::cos(5.0 * v + 3.0 * w);
}

void PhantomVoxelSource::fillRow(std::uint32_t j, std::uint32_t k, std::int16_t* row) const {
    const auto& d = geometry_.dims;
    const double v = (j + 0.5) / d[1] * 2.0 - 1.0;
    const double w = (k + 0.5) / d[2] * 2.0 - 1.0;
    const std::uint64_t rowSeed = mix(seed_ ^ (std::uint64_t(k) << 32 | j));
    for (std::uint32_t i = 0; i < d[0]; ++i) {
        const double u = (i + 0.5) / d[0] * 2.0 - 1.0;
        double hu = tissueAt(u, v, w);
        if (noiseHu_ > 0.0) {
            const std::uint64_t h = mix(rowSeed + i);
            // Sum of two uniforms: a cheap triangular approximation of Gaussian noise.
            const double n = (double(h & 0xffffffu) + double((h >> 24) & 0xffffffu)) / double(0x1000000) - 1.0;
            hu += n * noiseHu_ * 1.7;
        }
        row[i] = std::int16_t(std::lround(std::clamp(hu, -1024.0, 3071.0)));
    }
}

std::int16_t PhantomVoxelSource::voxel(std::uint32_t i, std::uint32_t j, std::uint32_t k) const {
    std::vector<std::int16_t> row(geometry_.dims[0]);
    fillRow(j, k, row.data());
    return row[i];
}

void PhantomVoxelSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const auto& d = geometry_.dims;
    auto* out = static_cast<std::int16_t*>(dst);
    const std::size_t rows = std::size_t(d[1]) * count;
    ThreadPool::shared().parallelFor(rows, [&](std::size_t b, std::size_t e) {
        for (std::size_t r = b; r < e; ++r) {
            const auto j = std::uint32_t(r % d[1]);
            const auto k = firstSlice + std::uint32_t(r / d[1]);
            fillRow(j, k, out + r * d[0]);
        }
    }, std::max<std::size_t>(1, 65536 / std::max<std::uint32_t>(1, d[0])));
}

}  // namespace hvx::core
