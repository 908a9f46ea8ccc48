#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <deque>
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
            slices_.pop_front();
            ++base_;
        }
    }
    /// Copies the E^3 brick (E = brick + 2*border) of node (x, y, row), clamping coordinates to
    /// the volume so that border and padding samples replicate the nearest voxel.
    void extractBrick(std::uint32_t x, std::uint32_t y, std::uint32_t row, T* out) const {
        const std::int64_t e = brick_ + 2 * border_;
        const std::int64_t x0 = std::int64_t(x) * brick_ - border_, y0 = std::int64_t(y) * brick_ - border_,
                           z0 = std::int64_t(row) * brick_ - border_;
        std::vector<std::uint32_t> xs(std::size_t(e), 0);
        for (std::int64_t a = 0; a < e; ++a) xs[std::size_t(a)] = clampAxis(x0 + a, 0);
        for (std::int64_t c = 0; c < e; ++c) {
            const T* s = slice(clampAxis(z0 + c, 2));
            for (std::int64_t b = 0; b < e; ++b) {
                const T* line = s + std::size_t(clampAxis(y0 + b, 1)) * dims_[0];
                for (std::int64_t a = 0; a < e; ++a) *out++ = line[xs[std::size_t(a)]];
            }
        }
    }
    /// The next level's slice from two consecutive slices (b == nullptr at an odd end):
    /// the mean of the existing samples of each 2×2×2 cell, or their most frequent value for
    /// label volumes (ties go to the smallest value).
    static std::vector<T> downsample(const T* a, const T* b, std::uint32_t w, std::uint32_t h, bool labels) {
        const std::uint32_t w2 = (w + 1) / 2, h2 = (h + 1) / 2;
        std::vector<T> out(std::size_t(w2) * h2);
        for (std::uint32_t y = 0; y < h2; ++y) {
            for (std::uint32_t x = 0; x < w2; ++x) {
                T vals[8];
                int n = 0;
                for (const T* s : {a, b}) {
                    if (!s) continue;
                    for (std::uint32_t yy = 2 * y; yy < std::min(h, 2 * y + 2); ++yy)
                        for (std::uint32_t xx = 2 * x; xx < std::min(w, 2 * x + 2); ++xx)
                            vals[n++] = s[std::size_t(yy) * w + xx];
                }
                out[std::size_t(y) * w2 + x] = labels ? mode(vals, n) : mean(vals, n);
            }
        }
        return out;
    }

    static T mean(const T* v, int n) {
        double sum = 0.0;
        for (int i = 0; i < n; ++i) sum += double(v[i]);
        const double m = sum / n;
        if constexpr (std::is_floating_point_v<T>) return T(m);
        else return T(std::llround(m));
    }
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
};

}  // namespace hvx::core
