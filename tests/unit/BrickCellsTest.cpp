#include <gtest/gtest.h>

#include <cstring>

#include "core/streaming/BrickCells.h"
#include "core/base/Error.h"
#include "core/appearance/TransferFunction.h"

using namespace hvx;

namespace {
/// A brick of `size` interior samples and `border` per side, every sample `background`.
template <class T>
core::Brick brickOf(std::uint32_t size, std::uint32_t border, core::ScalarType type, T background) {
    core::Brick b;
    b.edge = size + 2 * border;
    b.type = type;
    b.data.resize(std::size_t(b.edge) * b.edge * b.edge * sizeof(T));
    auto* v = reinterpret_cast<T*>(b.data.data());
    for (std::size_t i = 0; i < std::size_t(b.edge) * b.edge * b.edge; ++i) v[i] = background;
    return b;
}
template <class T>
void set(core::Brick& b, std::uint32_t x, std::uint32_t y, std::uint32_t z, T value) {
    reinterpret_cast<T*>(b.data.data())[(std::size_t(z) * b.edge + y) * b.edge + x] = value;
}
int cellIndex(int i, int j, int k) {
    return i + 4 * j + 16 * k;
}
}  // namespace

TEST(BrickCells, EachCellCoversTheSamplesItsBoxInterpolatesAndNoMore) {
    // 16^3 interior, border 2: cell (i, j, k) holds interior voxels [4i, 4i + 4) per axis, at
    // samples 2 + 4i ... 5 + 4i; interpolation anywhere in its box reads samples 1 + 4i ... 6 + 4i.
    auto b = brickOf<std::int16_t>(16, 2, core::ScalarType::Int16, 10);
    set<std::int16_t>(b, 6, 6, 6, 500);    // interior voxel (4, 4, 4): first voxel of cell (1, 1, 1)
    set<std::int16_t>(b, 13, 2, 2, -300);  // interior voxel (11, 0, 0): last voxel of cell (2, 0, 0)
    set<std::int16_t>(b, 0, 0, 0, 9999);   // outer border sample: no cell's box reaches it
    const auto cells = core::BrickCells::of(b, 16, 2);
    // 500 at sample 6 is read by the boxes of cells 0 and 1 on each axis (1 + 4·1 = 5 <= 6 <= 6 = 6 + 4·0).
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) {
                const auto r = cells.ranges[std::size_t(cellIndex(i, j, k))];
                const bool has500 = i <= 1 && j <= 1 && k <= 1;
                const bool hasMinus =
                    (i == 2 || i == 3) && j == 0 && k == 0;  // x sample 13: cells 2 (9..14), 3 (13..18)
                EXPECT_EQ(r.y, has500 ? 500.0f : 10.0f) << i << j << k;
                EXPECT_EQ(r.x, hasMinus ? -300.0f : 10.0f) << i << j << k;
            }
}

TEST(BrickCells, LossyCodesAreDecodedToTheValuesTheyStandFor) {
    auto b = brickOf<std::uint8_t>(8, 1, core::ScalarType::UInt8, 0);
    b.lossy8 = true;
    b.quantMin = -1000.0f;
    b.quantMax = 1550.0f;  // code c stands for -1000 + 10·c
    set<std::uint8_t>(b, 1, 1, 1, 255);
    const auto cells = core::BrickCells::of(b, 8, 1);
    EXPECT_FLOAT_EQ(cells.ranges[0].x, -1000.0f);
    EXPECT_FLOAT_EQ(cells.ranges[0].y, 1550.0f);
    EXPECT_FLOAT_EQ(cells.ranges[std::size_t(cellIndex(3, 3, 3))].y, -1000.0f);
}

TEST(BrickCells, VisibleBitsFollowTheTransferFunctionWithAMarginOfOneEntry) {
    auto b = brickOf<float>(8, 1, core::ScalarType::Float32, 0.0f);
    set<float>(b, 8, 8, 8, 900.0f);  // interior (7, 7, 7): cell (3, 3, 3) only
    const auto cells = core::BrickCells::of(b, 8, 1);
    // Transparent below 500, opaque from 600.
    const core::TransferFunction tf({{0, {0, 0, 0, 0}}, {500, {1, 1, 1, 0}}, {600, {1, 1, 1, 1}}, {1000, {1, 1, 1, 1}}},
                                    0.0, 1000.0);
    EXPECT_EQ(cells.visible(tf), std::uint64_t(1) << cellIndex(3, 3, 3));
    // Every cell shows under a transfer function opaque at 0 (one entry above it is opaque).
    const core::TransferFunction low({{0, {1, 1, 1, 0}}, {0.3, {1, 1, 1, 1}}, {1000, {1, 1, 1, 1}}}, 0.0, 1000.0);
    EXPECT_EQ(low.isEmpty(0.0, 0.0), false);
    EXPECT_EQ(cells.visible(low), ~std::uint64_t(0));
    const core::TransferFunction clear({{0, {0, 0, 0, 0}}, {1000, {0, 0, 0, 0}}}, 0.0, 1000.0);
    EXPECT_EQ(cells.visible(clear), 0u);
}

TEST(BrickCells, RefusesBricksWithoutBorderOrWithASizeNotDivisibleByFour) {
    EXPECT_THROW(core::BrickCells::of(brickOf<std::uint8_t>(8, 0, core::ScalarType::UInt8, 0), 8, 0), core::Error);
    EXPECT_THROW(core::BrickCells::of(brickOf<std::uint8_t>(6, 1, core::ScalarType::UInt8, 0), 6, 1), core::Error);
    EXPECT_THROW(core::BrickCells::of(brickOf<std::uint8_t>(8, 1, core::ScalarType::UInt8, 0), 8, 2), core::Error);
}

TEST(BrickCells, StraddlingBitsMarkTheCellsAnIsoSurfaceCanCross) {
    auto b = brickOf<std::uint16_t>(8, 1, core::ScalarType::UInt16, 100);
    set<std::uint16_t>(b, 1, 1, 1, 400);  // interior (0, 0, 0): cell (0, 0, 0) only
    const auto cells = core::BrickCells::of(b, 8, 1);
    EXPECT_EQ(cells.straddling(250.0), std::uint64_t(1));
    EXPECT_EQ(cells.straddling(100.0), ~std::uint64_t(0));  // every cell touches 100
    EXPECT_EQ(cells.straddling(401.0), 0u);
}
