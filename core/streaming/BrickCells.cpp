#include "core/streaming/BrickCells.h"

#include <algorithm>
#include <limits>

#include "core/base/Error.h"
#include "core/appearance/TransferFunction.h"

namespace hvx::core {

namespace {
template <class T>
void cellRanges(const T* v, std::uint32_t edge, std::uint32_t cell, std::uint32_t border,
                std::array<glm::vec2, BrickCells::kCount>& out) {
    for (int k = 0; k < BrickCells::kPerAxis; ++k)
        for (int j = 0; j < BrickCells::kPerAxis; ++j)
            for (int i = 0; i < BrickCells::kPerAxis; ++i) {
                // Interior voxels [c·cell, (c+1)·cell) sit at samples border + ...; their box
                // reaches half a voxel beyond, so interpolation reads one sample more each side.
                const std::uint32_t x0 = border + std::uint32_t(i) * cell - 1,
                                    y0 = border + std::uint32_t(j) * cell - 1,
                                    z0 = border + std::uint32_t(k) * cell - 1;
                T lo = std::numeric_limits<T>::max(), hi = std::numeric_limits<T>::lowest();
                for (std::uint32_t z = z0; z <= z0 + cell + 1; ++z)
                    for (std::uint32_t y = y0; y <= y0 + cell + 1; ++y) {
                        const T* row = v + (std::size_t(z) * edge + y) * edge + x0;
                        const auto [mn, mx] = std::minmax_element(row, row + cell + 2);
                        lo = std::min(lo, *mn);
                        hi = std::max(hi, *mx);
                    }
                out[std::size_t(i + BrickCells::kPerAxis * (j + BrickCells::kPerAxis * k))] =
                    glm::vec2(float(lo), float(hi));
            }
}
}  // namespace

BrickCells BrickCells::of(const Brick& brick, std::uint32_t brickSize, std::uint32_t border) {
    if (brickSize % kPerAxis != 0 || border < 1 || brick.edge != brickSize + 2 * border)
        throw Error("cell ranges need a brick size divisible by 4 and a border of at least one sample");
    BrickCells cells;
    const std::uint32_t cell = brickSize / kPerAxis;
    if (brick.lossy8) {
        cellRanges(brick.as<std::uint8_t>(), brick.edge, cell, border, cells.ranges);
        const float step = (brick.quantMax - brick.quantMin) / 255.0f;
        for (auto& r : cells.ranges) r = glm::vec2(brick.quantMin + r.x * step, brick.quantMin + r.y * step);
    } else {
        dispatchScalar(brick.type, [&](auto tag) {
            cellRanges(brick.as<decltype(tag)>(), brick.edge, cell, border, cells.ranges);
        });
    }
    return cells;
}

BrickCells BrickCells::ofSamples(const float* samples, std::uint32_t brickSize, std::uint32_t border) {
    if (brickSize % kPerAxis != 0 || border < 1)
        throw Error("cell ranges need a brick size divisible by 4 and a border of at least one sample");
    BrickCells cells;
    cellRanges(samples, brickSize + 2 * border, brickSize / kPerAxis, border, cells.ranges);
    return cells;
}

BrickCells BrickCells::ofSplit(const Brick& brick) {
    BrickCells cells;
    const std::uint32_t n = brick.edge, block = n / kPerAxis;
    if (n % kPerAxis != 0 || block == 0) {
        cells.ranges.fill(glm::vec2(-std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity()));
        return cells;
    }
    cells.ranges.fill(glm::vec2(std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()));
    for (std::uint32_t z = 0; z < n; ++z)
        for (std::uint32_t y = 0; y < n; ++y)
            for (std::uint32_t x = 0; x < n; ++x) {
                const SplitVoxel v = brick.cell(x, y, z);
                auto& r = cells.ranges[std::size_t(x / block + kPerAxis * (y / block + kPerAxis * (z / block)))];
                r = glm::vec2(std::min({r.x, v.front, v.back}), std::max({r.y, v.front, v.back}));
            }
    return cells;
}

std::uint64_t BrickCells::visible(const TransferFunction& tf, bool exact) const {
    const double entry = exact ? 0.0 : (tf.valueMax() - tf.valueMin()) / TransferFunction::kEntries;
    std::uint64_t bits = 0;
    for (std::size_t c = 0; c < ranges.size(); ++c)
        if (!tf.isEmpty(double(ranges[c].x) - entry, double(ranges[c].y) + entry)) bits |= std::uint64_t(1) << c;
    return bits;
}

std::uint64_t BrickCells::straddling(double value) const {
    std::uint64_t bits = 0;
    for (std::size_t c = 0; c < ranges.size(); ++c)
        if (double(ranges[c].x) <= value && value <= double(ranges[c].y)) bits |= std::uint64_t(1) << c;
    return bits;
}

}  // namespace hvx::core
