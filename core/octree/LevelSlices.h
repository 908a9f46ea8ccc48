#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <deque>
#include <mutex>
#include <type_traits>
#include <vector>

namespace hvx::core {

/// The k-slices of one octree level that are still needed, kept while the builder streams
/// through the volume; bricks are cut from here, and the next level's slices are filtered from
/// here. Holds at most brickSize + 2*border (+1) slices, so memory does not grow with depth.
///
/// Threading: extractBrick may run on several threads at once between push/drop calls.
template <class T>
class LevelSlices {
public:
    using Dims = std::array<std::uint32_t, 3>;
    LevelSlices(Dims dims, std::uint32_t brickSize, std::uint32_t border)
        : dims_(dims), brick_(brickSize), border_(border) {}

    const Dims& dims() const { return dims_; }
    std::size_t sliceVoxels() const { return std::size_t(dims_[0]) * dims_[1]; }
    /// Slices received so far (they arrive in order).
    std::uint32_t received() const { return base_ + std::uint32_t(slices_.size()); }
    void push(std::vector<T> slice) { slices_.push_back(std::move(slice)); }
    const T* slice(std::uint32_t z) const { return slices_[z - base_].data(); }
    /// Number of brick rows (node grid size along k).
    std::uint32_t rows() const { return (dims_[2] + brick_ - 1) / brick_; }
    /// True once every slice the bricks of `row` need (border included) has arrived.
    bool rowReady(std::uint32_t row) const {
        const std::uint64_t need = std::min<std::uint64_t>(dims_[2], std::uint64_t(row + 1) * brick_ + border_);
        return received() >= need;
    }
    /// Forgets slices that no row from `row` on needs.
    void dropBefore(std::uint32_t row) {
        const std::int64_t keep = std::int64_t(row) * brick_ - border_;
        while (!slices_.empty() && std::int64_t(base_) < keep) {
            {
                std::lock_guard lock(spareMutex_);
                if (spare_.size() < brick_) spare_.push_back(std::move(slices_.front()));
            }
            slices_.pop_front();
            ++base_;
        }
    }
    /// A slice-sized buffer, recycled from dropped slices when possible (saves page faults).
    /// Threading: any thread (the builder's reader thread takes, its main thread drops).
    std::vector<T> takeBuffer() {
        std::lock_guard lock(spareMutex_);
        if (spare_.empty()) return std::vector<T>(sliceVoxels());
        std::vector<T> v = std::move(spare_.back());
        spare_.pop_back();
        return v;
    }
    /// Copies the E^3 brick (E = brick + 2*border) of node (x, y, row), clamping coordinates to
    /// the volume so that border and padding samples replicate the nearest voxel.
    void extractBrick(std::uint32_t x, std::uint32_t y, std::uint32_t row, T* out) const {
        const std::int64_t e = brick_ + 2 * border_, w = dims_[0];
        const std::int64_t x0 = std::int64_t(x) * brick_ - border_, y0 = std::int64_t(y) * brick_ - border_,
                           z0 = std::int64_t(row) * brick_ - border_;
        // Each brick row is [replicated left edge | a run of real voxels | replicated right edge].
        const std::int64_t xa = std::clamp<std::int64_t>(x0, 0, w), xb = std::clamp<std::int64_t>(x0 + e, 0, w);
        const std::int64_t left = std::min(e, xa - x0), mid = std::max<std::int64_t>(0, xb - xa);
        const std::int64_t right = e - left - mid;
        for (std::int64_t c = 0; c < e; ++c) {
            const T* s = slice(clampAxis(z0 + c, 2));
            for (std::int64_t b = 0; b < e; ++b) {
                const T* line = s + std::size_t(clampAxis(y0 + b, 1)) * dims_[0];
                out = std::fill_n(out, left, line[0]);
                std::memcpy(out, line + xa, std::size_t(mid) * sizeof(T));
                out += mid;
                out = std::fill_n(out, right, line[w - 1]);
            }
        }
    }
    /// One row of the next level from rows (a0, a1) of one slice and (b0, b1) of the next; at an
    /// odd end the missing row or slice is passed again. Each output is the mean (or, for labels,
    /// the most frequent value, ties to the smallest) of its 2x2x2 cell with coordinates
    /// clamped: replicating a missing sample weights all present ones equally, so this is the
    /// mean / mode of the samples that exist.
    static void downsampleRow(const T* a0, const T* a1, const T* b0, const T* b1, std::uint32_t w, T* out,
                              bool labels) {
        const std::uint32_t w2 = (w + 1) / 2;
        for (std::uint32_t x = 0; x < w2; ++x) {
            const std::uint32_t i = 2 * x, j = std::min(2 * x + 1, w - 1);
            if (labels) {
                T v[8] = {a0[i], a0[j], a1[i], a1[j], b0[i], b0[j], b1[i], b1[j]};
                out[x] = mode(v, 8);
            } else if constexpr (std::is_floating_point_v<T>) {
                const double sum = double(a0[i]) + a0[j] + a1[i] + a1[j] + b0[i] + b0[j] + b1[i] + b1[j];
                out[x] = T(sum / 8.0);
            } else {
                const std::int64_t sum = std::int64_t(a0[i]) + a0[j] + a1[i] + a1[j] + b0[i] + b0[j] + b1[i] + b1[j];
                out[x] = T(roundedEighth(sum));
            }
        }
    }
    /// round(sum / 8), halves away from zero (as std::llround).
    static std::int64_t roundedEighth(std::int64_t sum) { return sum >= 0 ? (sum + 4) / 8 : -((-sum + 4) / 8); }

    static T mode(T* v, int n) {
        for (int i = 1; i < n; ++i)  // insertion sort: at most 8 values
            for (int j = i; j > 0 && v[j] < v[j - 1]; --j) std::swap(v[j], v[j - 1]);
        T best = v[0];
        int bestCount = 0;
        for (int i = 0; i < n;) {
            int j = i;
            while (j < n && v[j] == v[i]) ++j;
            if (j - i > bestCount) {
                bestCount = j - i;
                best = v[i];
            }
            i = j;
        }
        return best;
    }

private:
    std::uint32_t clampAxis(std::int64_t v, int axis) const {
        return std::uint32_t(std::clamp<std::int64_t>(v, 0, std::int64_t(dims_[std::size_t(axis)]) - 1));
    }

    Dims dims_;
    std::uint32_t brick_;
    std::uint32_t border_;
    std::uint32_t base_ = 0;
    std::deque<std::vector<T>> slices_;
    std::vector<std::vector<T>> spare_;
    std::mutex spareMutex_;
};

}  // namespace hvx::core
