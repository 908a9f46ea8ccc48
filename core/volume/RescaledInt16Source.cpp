#include "core/volume/RescaledInt16Source.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "core/base/Error.h"

namespace hvx::core {

RescaledInt16Source::RescaledInt16Source(std::unique_ptr<VoxelSource> inner, double physicalMin, double physicalMax)
    : inner_(std::move(inner)) {
    const auto& g = inner_->geometry();
    if (g.scalarType != ScalarType::Float32) throw Error(inner_->describe() + ": not a float volume");
    if (!std::isfinite(physicalMin) || !std::isfinite(physicalMax) || physicalMax < physicalMin)
        throw Error(inner_->describe() + ": its values are not finite, so they cannot be written as integers");
    geometry_ = g;
    geometry_.scalarType = ScalarType::Int16;
    // The rescale as a DICOM decimal string carries it (10 significant digits), so the error
    // measured here is the error of what is written; the step is rounded up so the range fits.
    const auto decimal = [](double v, bool up) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.10g", v);
        double d = std::strtod(buf, nullptr);
        if (up && d < v) d = std::nextafter(d, std::numeric_limits<double>::infinity()) * (1 + 1e-9);
        return d;
    };
    const double step = decimal(physicalMax > physicalMin ? (physicalMax - physicalMin) / 65534.0 : 1.0, true);
    geometry_.rescaleSlope = step;
    geometry_.rescaleIntercept = decimal(physicalMin + 32767.0 * step, false);  // stored -32767 is about physicalMin
    geometry_.valueMin = -32768;
    geometry_.valueMax = physicalMax > physicalMin ? 32767 : -32768;
}

void RescaledInt16Source::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const auto& g = inner_->geometry();
    const std::size_t n = std::size_t(g.dims[0]) * g.dims[1] * count;
    buffer_.resize(n);
    inner_->readSlices(firstSlice, count, buffer_.data());
    auto* out = static_cast<std::int16_t*>(dst);
    for (std::size_t i = 0; i < n; ++i) {
        const double physical = double(buffer_[i]) * g.rescaleSlope + g.rescaleIntercept;
        const double stored = std::round((physical - geometry_.rescaleIntercept) / geometry_.rescaleSlope);
        const auto s = std::int16_t(std::clamp(stored, -32768.0, 32767.0));
        out[i] = s;
        largestError_ = std::max(largestError_, std::abs(s * geometry_.rescaleSlope + geometry_.rescaleIntercept - physical));
    }
}

std::pair<double, double> RescaledInt16Source::physicalRange(VoxelSource& source) {
    const auto& g = source.geometry();
    if (g.scalarType != ScalarType::Float32) throw Error(source.describe() + ": not a float volume");
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    std::vector<float> slice(std::size_t(g.dims[0]) * g.dims[1]);
    for (std::uint32_t k = 0; k < g.dims[2]; ++k) {
        source.readSlices(k, 1, slice.data());
        for (float v : slice) {
            const double p = double(v) * g.rescaleSlope + g.rescaleIntercept;
            if (!std::isfinite(p))
                throw Error(source.describe() + ": slice " + std::to_string(k) + " holds a value that is not finite");
            lo = std::min(lo, p);
            hi = std::max(hi, p);
        }
    }
    return {lo, hi};
}

}  // namespace hvx::core
