// libFuzzer target: arbitrary bytes through the .hvo reader (header, node table, every brick's
// decompression). Checksums would stop almost every mutation at the first check, so the fuzzer
// makes them valid again before reading: what it explores is a forger's file, whose fields are
// hostile but whose checksums hold. Build with the `fuzz` preset; see tests/fuzz/run_fuzz.sh.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "core/base/Error.h"
#include "core/octree/BrickCodec.h"
#include "core/octree/HvoFormat.h"
#include "core/octree/OctreeReader.h"

namespace {
const std::string& scratchFile() {
    static const std::string path = [] {
        const char* dir = std::getenv("HVX_FUZZ_SCRATCH");
        return std::string(dir && *dir ? dir : "/tmp") + "/hvx-fuzz-" + std::to_string(::getpid()) + ".hvo";
    }();
    return path;
}

/// Gives the header, the node table and each in-range payload a valid checksum.
void fixChecksums(std::vector<std::uint8_t>& b) {
    using namespace hvx::core;
    if (b.size() < sizeof(hvo::FileHeader)) return;
    hvo::FileHeader h;
    std::memcpy(&h, b.data(), sizeof h);
    const std::uint64_t recordBytes = sizeof(hvo::NodeRecord);
    if (h.nodeTableOffset >= sizeof h && h.nodeTableOffset <= b.size() && h.nodeCount <= (b.size() - h.nodeTableOffset) / recordBytes) {
        auto* nodes = reinterpret_cast<hvo::NodeRecord*>(b.data() + h.nodeTableOffset);
        for (std::uint64_t i = 0; i < h.nodeCount; ++i) {
            hvo::NodeRecord n;
            std::memcpy(&n, &nodes[i], sizeof n);
            if (n.payloadOffset <= b.size() && n.payloadSize <= b.size() - n.payloadOffset) {
                n.checksum = BrickCodec::checksum(b.data() + n.payloadOffset, n.payloadSize);
                std::memcpy(&nodes[i], &n, sizeof n);
            }
        }
        h.nodeTableChecksum = BrickCodec::checksum(nodes, std::size_t(h.nodeCount * recordBytes));
    }
    h.headerChecksum = BrickCodec::checksum(&h, offsetof(hvo::FileHeader, headerChecksum));
    std::memcpy(b.data(), &h, sizeof h);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace hvx;
    std::vector<std::uint8_t> bytes(data, data + size);
    fixChecksums(bytes);
    {
        std::ofstream f(scratchFile(), std::ios::binary | std::ios::trunc);
        f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    }
    try {
        const auto reader = core::OctreeReader::open(scratchFile());
        for (std::uint32_t i = 0; i < reader->nodes().size() && i < 64; ++i) {
            try {
                (void)reader->readBrick(i);
            } catch (const core::Error&) {
            }
        }
    } catch (const core::Error&) {
    }
    return 0;
}
