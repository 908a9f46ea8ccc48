#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace hvx::dicom {

/// DICOM RLE Lossless (PS3.5 Annex G) for one frame: a 64-byte header of segment offsets and
/// PackBits-coded segments, one per byte plane (most significant first). Written here with
/// bounds checks on every offset and run, because DCMTK 3.6.7's RLE decoder reads out of
/// bounds on hostile fragments (found by the fuzzer; see tests/fuzz/regressions).
class RleDecoder {
public:
    /// Decodes into `out` (rows × columns samples of bytesPerSample bytes, little endian).
    /// Throws core::Error prefixed by `what` for any inconsistency.
    static void decode(const std::uint8_t* data, std::size_t size, std::size_t pixels, int bytesPerSample,
                       std::vector<std::uint8_t>& out, const std::string& what);
};

}  // namespace hvx::dicom
