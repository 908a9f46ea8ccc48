#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "dicom/DicomInstance.h"

namespace hvx::dicom {

/// Decodes frames of DICOM pixel data into stored values: uncompressed (little/big endian,
/// implicit/explicit VR, deflate), RLE, JPEG baseline/extended/lossless and JPEG-LS through
/// DCMTK's codecs, and JPEG 2000 through OpenJPEG. BitsStored is masked and signed data sign
/// extended, so the values are what the modality LUT (rescale) applies to.
/// Keeps the last file loaded, so the frames of a multi-frame object decode without reloading.
///
/// Threading: one object per thread.
class PixelDecoder {
public:
    PixelDecoder();
    ~PixelDecoder();
    PixelDecoder(const PixelDecoder&) = delete;
    PixelDecoder& operator=(const PixelDecoder&) = delete;
    /// Decodes `frame` of `instance` into out (rows × columns values, row by row). Throws
    /// core::Error naming the file and the reason (truncated, unsupported syntax, bad codestream).
    void decode(const DicomInstance& instance, std::uint32_t frame, std::vector<std::int32_t>& out);
    /// The largest frame decoded (16384²): a header claiming more is refused before any
    /// decoder sizes a buffer from it.
    static constexpr std::uint64_t kMaxFramePixels = std::uint64_t(16384) * 16384;

private:
    void decodeFrame(const DicomInstance& instance, std::uint32_t frame, std::vector<std::int32_t>& out);
    /// Float and Double Float Pixel Data: each sample's float32 bits in an int32.
    void decodeFloatFrame(const DicomInstance& instance, std::uint32_t frame, std::vector<std::int32_t>& out);
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace hvx::dicom
