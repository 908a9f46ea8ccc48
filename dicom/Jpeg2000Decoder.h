#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace hvx::dicom {

/// Decodes one JPEG 2000 codestream (raw J2K or a JP2 file) of a single-component image with
/// OpenJPEG, which DCMTK 3.6.7's free codecs lack.
class Jpeg2000Decoder {
public:
    /// Decodes into out (width × height samples). Throws core::Error prefixed by `what` when the
    /// stream is malformed, not single-component, or not `width` × `height`.
    static void decode(const std::uint8_t* data, std::size_t size, std::uint32_t width, std::uint32_t height,
                       std::vector<std::int32_t>& out, const std::string& what);
};

}  // namespace hvx::dicom
