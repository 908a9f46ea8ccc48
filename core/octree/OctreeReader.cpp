#include "core/octree/OctreeReader.h"
#include "core/octree/SplitVoxel.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>

#include "core/octree/BrickCodec.h"
#include "core/octree/OctreeLayout.h"

namespace hvx::core {

namespace {
bool readFully(int fd, void* dst, std::size_t size, std::uint64_t offset) {
    auto* p = static_cast<char*>(dst);
    while (size > 0) {
        const ssize_t n = ::pread(fd, p, size, off_t(offset));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        p += n;
        size -= std::size_t(n);
        offset += std::uint64_t(n);
    }
    return true;
}
}  // namespace

std::unique_ptr<OctreeReader> OctreeReader::open(const std::string& path, bool acceptSplitVoxels) {
    std::unique_ptr<OctreeReader> r(new OctreeReader());
    r->path_ = path;
    r->fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (r->fd_ < 0) throw Error(path + ": cannot open (" + std::strerror(errno) + ")");
    r->load();
    if (r->splitVoxels() && !acceptSplitVoxels)
        throw Error(path + ": a split-voxel octree (cells with two values and a plane, not voxels), which only "
                           "`holovox-cli info` and `holovox-cli render --cpu` read yet; open the volume's own octree");
    return r;
}

std::array<std::uint32_t, 3> OctreeReader::sourceDims() const {
    if (!splitVoxels()) return geometry_.dims;
    return {header_.split.sourceDims[0], header_.split.sourceDims[1], header_.split.sourceDims[2]};
}

OctreeReader::~OctreeReader() {
    if (fd_ >= 0) ::close(fd_);
}

void OctreeReader::load() {
    const auto bad = [this](const std::string& why) { return Error(path_ + ": not a valid .hvo file (" + why + ")"); };
    struct stat st {};
    if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) throw bad("not a regular file");
    if (std::uint64_t(st.st_size) < sizeof header_ || !readFully(fd_, &header_, sizeof header_, 0))
        throw bad("file is shorter than the header");
    auto& h = header_;
    if (std::memcmp(h.magic, hvo::kMagic, sizeof h.magic) != 0) throw bad("wrong magic number");
    if (h.version > hvo::kVersionSplitVoxels)
        throw bad("format version " + std::to_string(h.version) + ", written by a newer Holovox; this one reads versions 1 and 2");
    if (h.version == 0) throw bad("unsupported version 0");
    const bool split = (h.flags & hvo::FileSplitVoxels) != 0;
    if (split != (h.version == hvo::kVersionSplitVoxels))
        throw bad("version " + std::to_string(h.version) + (split ? " marked as" : " not marked as") + " split-voxels");
    if (BrickCodec::checksum(&h, offsetof(hvo::FileHeader, headerChecksum)) != h.headerChecksum)
        throw bad("header checksum mismatch");
    if (!h.complete) throw bad("the build that wrote it did not finish");
    if (h.fileSize != std::uint64_t(st.st_size))
        throw bad("file is " + std::to_string(st.st_size) + " bytes, header says " + std::to_string(h.fileSize) +
                  " (truncated?)");
    if (!isValidScalarType(h.scalarType)) throw bad("unknown scalar type");
    if (h.codec > 2) throw bad("unknown codec");
    if (h.brickSize < 1 || h.brickSize > 256 || h.border > 8) throw bad("brick size or border out of range");
    if (split) {
        if (h.border != 0 || h.split.n < 2 || h.split.n > 8 || h.split.overlap > 4 ||
            !isValidScalarType(h.scalarType) || ScalarType(h.scalarType) == ScalarType::Float32)
            throw bad("split-voxel parameters out of range");
        for (int a = 0; a < 3; ++a)
            if (h.split.sourceDims[a] == 0 || (std::uint64_t(h.split.sourceDims[a]) + h.split.n - 1) / h.split.n != h.dims[a])
                throw bad("the cell grid does not match the source volume's dimensions");
    }
    const std::uint64_t tableBytes = h.nodeCount * sizeof(hvo::NodeRecord);
    if (h.nodeCount == 0 || h.nodeCount > (1ull << 32) || h.nodeTableOffset < sizeof h ||
        h.nodeTableOffset > h.fileSize || tableBytes != h.fileSize - h.nodeTableOffset)
        throw bad("node table out of bounds");

    VolumeGeometry& g = geometry_;
    for (int a = 0; a < 3; ++a) {
        g.dims[std::size_t(a)] = h.dims[a];
        g.spacing[a] = h.spacing[a];
        g.origin[a] = h.origin[a];
        for (int r = 0; r < 3; ++r) g.direction[a][r] = h.direction[3 * a + r];
    }
    g.scalarType = ScalarType(h.scalarType);
    g.rescaleSlope = h.rescaleSlope;
    g.rescaleIntercept = h.rescaleIntercept;
    g.valueMin = h.valueMin;
    g.valueMax = h.valueMax;
    g.modality.assign(h.modality, strnlen(h.modality, sizeof h.modality));
    g.frameOfReferenceUid.assign(h.frameOfReferenceUid, strnlen(h.frameOfReferenceUid, sizeof h.frameOfReferenceUid));
    g.isLabel = (h.flags & hvo::FileLabels) != 0;
    g.monochrome1 = (h.flags & hvo::FileMonochrome1) != 0;
    g.notHounsfield = (h.flags & hvo::FileNotHounsfield) != 0;
    g.spacingAssumed = (h.flags & hvo::FileSpacingAssumed) != 0;
    g.orientationAssumed = (h.flags & hvo::FileOrientationAssumed) != 0;
    for (const auto& w : h.windows)
        if (w.width > 0 && std::isfinite(w.width) && std::isfinite(w.centre))
            g.windows.push_back({std::string(w.name, strnlen(w.name, sizeof w.name)), w.centre, w.width});
    try {
        g.validate(path_);
    } catch (const Error& e) {
        throw bad(e.what());
    }

    // The structure must be exactly the one the dimensions imply: a hostile table cannot send
    // traversal out of bounds or into cycles. The counts come first, by arithmetic: the table's
    // size is bounded by the file's, so nothing below is sized from an unchecked header field.
    const auto counts = OctreeLayout::count(g.dims, h.brickSize);
    if (counts.nodes != h.nodeCount || counts.levels != int(h.levelCount))
        throw bad("node count " + std::to_string(h.nodeCount) + " does not match the volume dimensions " +
                  std::to_string(g.dims[0]) + "x" + std::to_string(g.dims[1]) + "x" + std::to_string(g.dims[2]) +
                  " in bricks of " + std::to_string(h.brickSize));
    const OctreeLayout layout(g.dims, h.brickSize);
    if (layout.levelCount() != int(h.levelCount) || layout.nodes().size() != h.nodeCount)
        throw bad("node count does not match the volume dimensions");
    nodes_.resize(std::size_t(h.nodeCount));
    if (!readFully(fd_, nodes_.data(), std::size_t(tableBytes), h.nodeTableOffset)) throw bad("cannot read node table");
    if (BrickCodec::checksum(nodes_.data(), std::size_t(tableBytes)) != h.nodeTableChecksum)
        throw bad("node table checksum mismatch");
    const auto& ref = layout.nodes();
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        const auto& n = nodes_[i];
        const auto& e = ref[i];
        if (n.parent != e.parent || n.firstChild != e.firstChild || n.childMask != e.childMask || n.x != e.x ||
            n.y != e.y || n.z != e.z || n.level != e.level)
            throw bad("node " + std::to_string(i) + " has an inconsistent structure");
        if (!(n.flags & hvo::NodeEmpty) && (n.payloadOffset < sizeof h || n.payloadOffset > h.nodeTableOffset ||
                                             n.payloadSize > h.nodeTableOffset - n.payloadOffset))
            throw bad("payload of node " + std::to_string(i) + " is out of bounds");
    }
}

Brick OctreeReader::readBrick(std::uint32_t node) const {
    if (node >= nodes_.size()) throw Error(path_ + ": node " + std::to_string(node) + " does not exist");
    const auto& n = nodes_[node];
    Brick b;
    b.node = node;
    b.edge = brickEdge();
    b.type = geometry_.scalarType;
    const std::size_t samples = std::size_t(b.edge) * b.edge * b.edge;
    const auto where = [&] {
        return path_ + ": brick of node " + std::to_string(node) + " (level " + std::to_string(n.level) + ", " +
               std::to_string(n.x) + "," + std::to_string(n.y) + "," + std::to_string(n.z) + ")";
    };
    if (n.flags & hvo::NodeEmpty) {
        b.empty = true;
        b.data.resize(samples * scalarSize(b.type));
        dispatchScalar(b.type, [&](auto tag) {
            using T = decltype(tag);
            std::fill_n(reinterpret_cast<T*>(b.data.data()), samples, T(n.minValue));
        });
        return b;
    }
    // One read, checksum and decompression for every kind of payload; what it decodes to:
    // split-voxel cells (unshuffled), lossy 8-bit codes, or samples of the volume's type.
    std::size_t bytes = 0, width = 1;
    if (splitVoxels()) {
        b.splitVoxels = true;
        bytes = samples * SplitVoxel::encodedSize(scalarSize(b.type));
    } else {
        b.lossy8 = (n.flags & hvo::NodeLossy8) != 0;
        if (b.lossy8) {
            b.type = ScalarType::UInt8;
            b.quantMin = n.quantMin;
            b.quantMax = n.quantMax;
        }
        bytes = samples * scalarSize(b.type);
        width = (header_.flags & hvo::FileShuffled) ? scalarSize(b.type) : 1;
    }
    std::vector<std::byte> packed(n.payloadSize);
    if (!readFully(fd_, packed.data(), packed.size(), n.payloadOffset))
        throw CorruptBrickError(where() + " cannot be read (" + std::strerror(errno) + ")", node);
    if (BrickCodec::checksum(packed.data(), packed.size()) != n.checksum)
        throw CorruptBrickError(where() + " is corrupt (checksum mismatch)", node);
    b.data.resize(bytes);
    if (!BrickCodec::decompress(hvo::Codec(header_.codec), packed.data(), packed.size(), b.data.data(), bytes, width))
        throw CorruptBrickError(where() + " is corrupt (does not decompress)", node);
    return b;
}

}  // namespace hvx::core
