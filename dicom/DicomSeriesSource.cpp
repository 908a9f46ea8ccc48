#include "dicom/DicomSeriesSource.h"

#include <cstring>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/base/Error.h"
#include "core/base/ThreadPool.h"
#include "dicom/PixelDecoder.h"

namespace hvx::dicom {

DicomSeriesSource::DicomSeriesSource(SeriesVolume volume) : volume_(std::move(volume)) {
    if (volume_.slices.empty()) throw core::Error("series " + volume_.seriesUid + " has no slices");
    const auto& s0 = volume_.slices.front();
    const DicomInstance& first = volume_.instances[s0.instance];
    // Before anything is sized from Rows and Columns (the builder's slabs, the decoders).
    if (std::uint64_t(first.rows) * first.columns > PixelDecoder::kMaxFramePixels)
        throw core::Error(first.path + ": a frame of " + std::to_string(first.columns) + " × " +
                          std::to_string(first.rows) + " pixels cannot be right (Holovox decodes frames of up to "
                          "16384 × 16384)");
    paddingStored_ = paddingStoredOf(volume_);
    paddingPhysical_ = paddingStored_ * s0.rescaleSlope + s0.rescaleIntercept;
}

double DicomSeriesSource::paddingStoredOf(const SeriesVolume& v) {
    const auto& s0 = v.slices.front();
    if (v.geometry.hounsfield()) return (core::VolumeGeometry::kCtPaddingHu - s0.rescaleIntercept) / s0.rescaleSlope;
    const DicomInstance& first = v.instances[s0.instance];
    return first.pixelRepresentation == 1 ? -double(1u << (first.bitsStored - 1)) : 0.0;
}

double DicomSeriesSource::paddingValue(const SeriesVolume& v) {
    const auto& s0 = v.slices.front();
    const double stored = paddingStoredOf(v);
    if (v.applyRescale) return stored * s0.rescaleSlope + s0.rescaleIntercept;  // float values: exact
    // Stored values: rounded and held to the stored type, as writeSlice writes them.
    double held = 0.0;
    core::dispatchScalar(v.geometry.scalarType, [&](auto tag) {
        using T = decltype(tag);
        held = std::clamp(std::round(stored), double(std::numeric_limits<T>::lowest()), double(std::numeric_limits<T>::max()));
    });
    return held * v.geometry.rescaleSlope + v.geometry.rescaleIntercept;
}

std::string DicomSeriesSource::describe() const { return "series " + volume_.seriesUid + " (" + volume_.label + ")"; }

const std::vector<std::int32_t>& DicomSeriesSource::input(std::size_t slice) {
    auto it = decoded_.find(slice);
    if (it != decoded_.end()) return it->second;
    // Decode this slice and the next few on all cores; forget slices behind us.
    while (!decoded_.empty() && decoded_.begin()->first + 1 < slice) decoded_.erase(decoded_.begin());
    const std::size_t ahead = std::min<std::size_t>(volume_.slices.size() - slice, 8);
    std::vector<std::vector<std::int32_t>> out(ahead);
    core::ThreadPool::shared().parallelFor(ahead, [&](std::size_t b, std::size_t e) {
        thread_local PixelDecoder decoder;
        for (std::size_t i = b; i < e; ++i) {
            const SliceRef& s = volume_.slices[slice + i];
            decoder.decode(volume_.instances[s.instance], s.frame, out[i]);
        }
    });
    for (std::size_t i = 0; i < ahead; ++i) decoded_[slice + i] = std::move(out[i]);
    return decoded_[slice];
}

template <class T>
void DicomSeriesSource::writeSlice(std::uint32_t z, T* out) {
    const auto& g = volume_.geometry;
    const std::size_t n = std::size_t(g.dims[0]) * g.dims[1];
    const auto& slices = volume_.slices;
    std::size_t a = z, b = z;
    double t = 0.0;
    if (volume_.resample) {
        const double along = slices.front().along + (slices.back().along - slices.front().along) *
                                                        (g.dims[2] > 1 ? double(z) / (g.dims[2] - 1) : 0.0);
        b = std::size_t(std::lower_bound(slices.begin(), slices.end(), along,
                                         [](const SliceRef& s, double v) { return s.along < v; }) -
                        slices.begin());
        b = std::min(b, slices.size() - 1);
        a = b > 0 ? b - 1 : 0;
        const double span = slices[b].along - slices[a].along;
        t = span > 0 ? std::clamp((along - slices[a].along) / span, 0.0, 1.0) : 0.0;
        if (t == 0.0) b = a;
        if (t == 1.0) a = b;
    }
    const auto& va = input(a);
    const auto& vb = input(b);
    if (va.size() < n || vb.size() < n) throw core::Error(describe() + ": slice has fewer pixels than the series");
    const DicomInstance& ia = volume_.instances[slices[a].instance];
    const DicomInstance& ib = volume_.instances[slices[b].instance];
    if constexpr (!std::is_floating_point_v<T>) {
        if (a == b && !volume_.applyRescale) {
            // Stored values straight through (the common case): integer work only.
            const std::int32_t lo = std::numeric_limits<T>::lowest(), hi = std::numeric_limits<T>::max();
            const auto padTo = std::int32_t(std::clamp<double>(std::round(paddingStored_), lo, hi));
            const auto [padLow, padHigh] = ia.paddingRange();  // stored padding values: integers here
            const auto pLo = std::int64_t(std::ceil(padLow)), pHi = std::int64_t(std::floor(padHigh));
            for (std::size_t i = 0; i < n; ++i) {
                const std::int32_t v = va[i];
                out[i] = T(v >= pLo && v <= pHi ? padTo : std::clamp(v, lo, hi));
            }
            return;
        }
    }
    const auto padA = ia.paddingRange(), padB = ib.paddingRange();
    auto value = [&](const DicomInstance& in, const std::pair<double, double>& pad, const SliceRef& s,
                     std::int32_t v) -> double {
        // The decoder hands 32-bit samples over as int32: unsigned ones at or above 2^31 are
        // taken back as unsigned here, never as negative numbers.
        double raw = in.bitsAllocated == 32 && in.pixelRepresentation == 0 ? double(std::uint32_t(v)) : double(v);
        if (in.floatPixelBits) {  // Float / Double Float Pixel Data: the decoder hands over float bits
            float f;
            std::memcpy(&f, &v, sizeof f);
            raw = double(f);
        }
        // Padding is one value for the whole series (-1024 HU for CT), whatever each slice's own
        // rescale: converted with the first slice's, never with this one's.
        if (raw >= pad.first && raw <= pad.second) return volume_.applyRescale ? paddingPhysical_ : paddingStored_;
        return volume_.applyRescale ? raw * s.rescaleSlope + s.rescaleIntercept : raw;
    };
    for (std::size_t i = 0; i < n; ++i) {
        double x = value(ia, padA, slices[a], va[i]);
        if (b != a) x += t * (value(ib, padB, slices[b], vb[i]) - x);
        if constexpr (std::is_floating_point_v<T>) {
            out[i] = T(x);
        } else {
            x = std::round(x);
            out[i] = T(std::clamp(x, double(std::numeric_limits<T>::lowest()), double(std::numeric_limits<T>::max())));
        }
    }
}

void DicomSeriesSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const auto& g = volume_.geometry;
    const std::size_t n = std::size_t(g.dims[0]) * g.dims[1];
    core::dispatchScalar(g.scalarType, [&](auto tag) {
        using T = decltype(tag);
        for (std::uint32_t z = 0; z < count; ++z) writeSlice<T>(firstSlice + z, static_cast<T*>(dst) + z * n);
    });
}

}  // namespace hvx::dicom
