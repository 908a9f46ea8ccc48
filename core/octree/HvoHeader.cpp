#include "core/octree/HvoHeader.h"

#include <algorithm>
#include <cstddef>
#include <cstring>

#include "core/octree/BrickCodec.h"

namespace hvx::core::hvo {

FileHeader startHeader(const VolumeGeometry& g, const BuildOptions& opt, int levels) {
    FileHeader h;
    std::memset(&h, 0, sizeof h);
    std::memcpy(h.magic, kMagic, sizeof h.magic);
    h.version = kVersion;
    h.headerSize = sizeof(FileHeader);
    for (int a = 0; a < 3; ++a) {
        h.dims[a] = g.dims[std::size_t(a)];
        h.spacing[a] = g.spacing[a];
        h.origin[a] = g.origin[a];
        for (int r = 0; r < 3; ++r) h.direction[3 * a + r] = g.direction[a][r];
    }
    h.brickSize = opt.brickSize;
    h.border = opt.border;
    h.levelCount = std::uint32_t(levels);
    h.scalarType = std::uint32_t(g.scalarType);
    h.codec = std::uint32_t(opt.codec);
    h.flags = (opt.labels || g.isLabel ? FileLabels : 0u) | (opt.lossy8 ? FileLossy8 : 0u) |
              (opt.emptyBelow ? FileEmptyThreshold : 0u) | FileShuffled |
              (g.monochrome1 ? FileMonochrome1 : 0u) | (g.spacingAssumed ? FileSpacingAssumed : 0u) |
              (g.orientationAssumed ? FileOrientationAssumed : 0u) | (g.notHounsfield ? FileNotHounsfield : 0u);
    h.rescaleSlope = g.rescaleSlope;
    h.rescaleIntercept = g.rescaleIntercept;
    h.emptyBelow = opt.emptyBelow ? *opt.emptyBelow : 0.0;
    const std::string& modality = opt.modality.empty() ? g.modality : opt.modality;
    std::strncpy(h.modality, modality.c_str(), sizeof h.modality - 1);
    std::memcpy(h.frameOfReferenceUid, g.frameOfReferenceUid.data(),
                std::min(g.frameOfReferenceUid.size(), sizeof h.frameOfReferenceUid));
    for (std::size_t i = 0; i < std::min<std::size_t>(4, g.windows.size()); ++i) {
        h.windows[i].centre = g.windows[i].centre;
        h.windows[i].width = g.windows[i].width;
        std::strncpy(h.windows[i].name, g.windows[i].name.c_str(), sizeof h.windows[i].name - 1);
    }
    return h;
}

void finishFile(FileHeader& h, const std::vector<NodeRecord>& nodes, AtomicFileWriter& out) {
    h.valueMin = nodes[0].minValue;
    h.valueMax = nodes[0].maxValue;
    h.nodeCount = nodes.size();
    h.nodeTableChecksum = BrickCodec::checksum(nodes.data(), nodes.size() * sizeof(NodeRecord));
    h.nodeTableOffset = out.append(nodes.data(), nodes.size() * sizeof(NodeRecord));
    h.fileSize = out.size();
    h.complete = 1;
    h.headerChecksum = BrickCodec::checksum(&h, offsetof(FileHeader, headerChecksum));
    out.writeAt(0, &h, sizeof h);
    out.commit();
}

}  // namespace hvx::core::hvo
