// libFuzzer target: arbitrary bytes through DICOM header reading, series assembly and pixel
// decoding. Build with the `fuzz` preset; see tests/fuzz/run_fuzz.sh.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/base/Error.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/PixelDecoder.h"
#include "dicom/SeriesAssembler.h"

namespace {
const std::string& scratchFile() {
    static const std::string path = [] {
        const char* dir = std::getenv("HVX_FUZZ_SCRATCH");  // run_fuzz.sh's own folder
        return std::string(dir && *dir ? dir : "/tmp") + "/hvx-fuzz-" + std::to_string(::getpid()) + ".dcm";
    }();
    return path;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace hvx;
    // Holovox reads DICOM from files (scanner, decoder): give it these bytes as one.
    if (FILE* f = std::fopen(scratchFile().c_str(), "wb")) {
        std::fwrite(data, 1, size, f);
        std::fclose(f);
    }
    dicom::DicomInstance in;
    try {
        if (dicom::DicomHeaderReader::read(scratchFile(), in) != dicom::DicomHeaderReader::Kind::Dicom) return 0;
    } catch (const core::Error&) {
        return 0;
    }
    std::vector<std::string> notes;
    const auto volumes = dicom::SeriesAssembler::assemble({in}, notes);
    if (volumes.empty()) return 0;
    dicom::PixelDecoder decoder;
    std::vector<std::int32_t> pixels;
    for (std::uint32_t frame = 0; frame < in.frames && frame < 4; ++frame) {
        try {
            decoder.decode(in, frame, pixels);
        } catch (const core::Error&) {
            break;
        }
    }
    return 0;
}
