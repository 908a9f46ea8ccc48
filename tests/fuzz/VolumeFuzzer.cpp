// libFuzzer target: arbitrary bytes through the volume-file readers Holovox writes itself: the
// MetaImage header and its raw or compressed data, NRRD (raw and gzip), NIfTI, legacy VTK. The first byte
// picks the format (the file's extension), the rest is the file. Files that would go to VTK's
// reader (a third party's, not instrumented) are left out. Every voxel of a volume of up to
// 16 MiB is read, in slabs. Build with the `fuzz` preset; see tests/fuzz/run_fuzz.sh.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "core/base/Error.h"
#include "core/volume/LegacyVtkHeader.h"
#include "core/volume/MetaImageHeader.h"
#include "core/volume/VoxelSourceFactory.h"

namespace {
std::string scratchFile(const char* extension) {
    const char* dir = std::getenv("HVX_FUZZ_SCRATCH");
    return std::string(dir && *dir ? dir : "/tmp") + "/hvx-fuzz-" + std::to_string(::getpid()) + extension;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace hvx;
    if (size < 1) return 0;
    static const char* const extensions[] = {".mha", ".nrrd", ".nii", ".nii.gz", ".vtk"};
    const int format = data[0] % 5;
    const std::string path = scratchFile(extensions[format]);
    {
        std::ofstream f(path, std::ios::binary | std::ios::trunc);
        f.write(reinterpret_cast<const char*>(data + 1), std::streamsize(size - 1));
    }
    try {
        if (format == 0 && !core::MetaImageHeader::read(path).streamReason.empty()) return 0;  // VTK's
        if (format == 4 && !core::LegacyVtkHeader::read(path).streamReason.empty()) return 0;  // VTK's
        const auto source = core::VoxelSourceFactory::open(path);
        const auto& g = source->geometry();
        if (g.byteSize() > (16u << 20)) return 0;
        const std::size_t slice = std::size_t(g.byteSize() / g.dims[2]);
        std::vector<unsigned char> slab(slice * 7);
        for (std::uint32_t k = 0; k < g.dims[2]; k += 7) source->readSlices(k, std::min<std::uint32_t>(7, g.dims[2] - k), slab.data());
    } catch (const core::Error&) {
    }
    return 0;
}
