#include "core/volume/NrrdWriter.h"

#include <algorithm>
#include <vector>

#include "core/base/AtomicFileWriter.h"
#include "core/volume/NrrdHeader.h"

namespace hvx::core {

void NrrdWriter::write(VoxelSource& source, const std::string& path, JobContext& job) {
    const auto& g = source.geometry();
    AtomicFileWriter out(path);
    const std::string header = NrrdHeader::format(g);
    out.append(header.data(), header.size());
    const std::size_t sliceBytes = std::size_t(g.dims[0]) * g.dims[1] * scalarSize(g.scalarType);
    const std::uint32_t slab = std::max<std::uint32_t>(1, std::uint32_t((64u << 20) / std::max<std::size_t>(1, sliceBytes)));
    std::vector<char> buffer;
    for (std::uint32_t z = 0; z < g.dims[2]; z += slab) {
        job.throwIfCancelled();
        const std::uint32_t n = std::min(slab, g.dims[2] - z);
        buffer.resize(sliceBytes * n);
        source.readSlices(z, n, buffer.data());
        out.append(buffer.data(), buffer.size());
        job.report(double(z + n) / g.dims[2], "writing");
    }
    out.commit();
}

}  // namespace hvx::core
