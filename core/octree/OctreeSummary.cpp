#include "core/octree/OctreeSummary.h"

#include <cstdio>
#include <sstream>

#include "core/octree/BrickCodec.h"

namespace hvx::core {

namespace {
std::string bytes(double b) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    int u = 0;
    while (b >= 1024.0 && u < 4) {
        b /= 1024.0;
        ++u;
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f %s", b, units[u]);
    return buf;
}
}  // namespace

OctreeSummary OctreeSummary::of(const OctreeReader& reader) {
    OctreeSummary s;
    const auto& h = reader.header();
    s.levels.resize(std::size_t(reader.levelCount()));
    for (const auto& n : reader.nodes()) {
        auto& l = s.levels[n.level];
        ++l.nodeCount;
        if (n.flags & hvo::NodeEmpty) ++l.emptyCount;
        l.payloadBytes += n.payloadSize;
        l.nodes[0] = std::max<std::uint32_t>(l.nodes[0], n.x + 1u);
        l.nodes[1] = std::max<std::uint32_t>(l.nodes[1], n.y + 1u);
        l.nodes[2] = std::max<std::uint32_t>(l.nodes[2], n.z + 1u);
    }
    std::uint32_t d[3] = {h.dims[0], h.dims[1], h.dims[2]};
    for (auto& l : s.levels) {
        for (int a = 0; a < 3; ++a) {
            l.dims[a] = d[a];
            d[a] = (d[a] + 1) / 2;
        }
        s.nodeCount += l.nodeCount;
        s.emptyCount += l.emptyCount;
    }
    s.fileBytes = h.fileSize;
    const auto source = reader.sourceDims();  // a split-voxel octree stands for its source's voxels
    s.volumeBytes = std::uint64_t(source[0]) * source[1] * source[2] * scalarSize(reader.geometry().scalarType);
    s.rawBrickBytes = h.rawBrickBytes;
    return s;
}

std::string OctreeSummary::format(const OctreeReader& reader) const {
    const auto& g = reader.geometry();
    const auto& h = reader.header();
    std::ostringstream o;
    char buf[256];
    o << reader.path() << "\n";
    // A split-voxel octree's geometry is its grid of cells: said as the source volume's.
    const double n = reader.splitVoxels() ? double(h.split.n) : 1.0;
    const auto source = reader.sourceDims();
    const glm::dvec3 spacing = g.spacing / n;
    const glm::dvec3 origin = g.origin - g.direction * (spacing * ((n - 1.0) / 2.0));
    std::snprintf(buf, sizeof buf, "  volume      %u x %u x %u %s, %s%s\n", source[0], source[1], source[2],
                  std::string(scalarName(g.scalarType)).c_str(), g.modality.c_str(), g.isLabel ? " (labels)" : "");
    o << buf;
    std::snprintf(buf, sizeof buf, "  spacing     %.4g x %.4g x %.4g mm%s\n", spacing.x, spacing.y, spacing.z,
                  g.spacingAssumed ? " (not in the source: 1 mm assumed, lengths are not mm)" : "");
    o << buf;
    std::snprintf(buf, sizeof buf, "  origin      (%.2f, %.2f, %.2f) mm LPS\n", origin.x, origin.y, origin.z);
    o << buf;
    std::snprintf(buf, sizeof buf, "  direction   i=(%.3f,%.3f,%.3f) j=(%.3f,%.3f,%.3f) k=(%.3f,%.3f,%.3f)%s\n",
                  g.direction[0].x, g.direction[0].y, g.direction[0].z, g.direction[1].x, g.direction[1].y,
                  g.direction[1].z, g.direction[2].x, g.direction[2].y, g.direction[2].z,
                  g.orientationAssumed ? " (not in the source: assumed, left and right unknown)" : "");
    o << buf;
    std::snprintf(buf, sizeof buf, "  values      stored [%g, %g], rescale %g * v + %g\n", g.valueMin, g.valueMax,
                  g.rescaleSlope, g.rescaleIntercept);
    o << buf;
    std::snprintf(buf, sizeof buf, "  bricks      %u^3 interior, border %u, codec %s%s\n", h.brickSize, h.border,
                  std::string(BrickCodec::name(hvo::Codec(h.codec))).c_str(),
                  (h.flags & hvo::FileLossy8) ? ", lossy 8-bit" : "");
    o << buf;
    if (h.flags & hvo::FileLossy8) {
        std::snprintf(buf, sizeof buf, "  lossy error RMS %.4g, max %.4g (stored units)\n", h.lossyRmsError,
                      h.lossyMaxError);
        o << buf;
    }
    if (h.flags & hvo::FileEmptyThreshold) {
        std::snprintf(buf, sizeof buf, "  empty below %g\n", h.emptyBelow);
        o << buf;
    }
    if (reader.splitVoxels()) {
        std::snprintf(buf, sizeof buf, "  split-voxels cells of %u voxels (fitted with %u overlap layers) for %u x %u x %u voxels\n",
                      unsigned(h.split.n), unsigned(h.split.overlap), source[0], source[1], source[2]);
        o << buf;
    }
    o << "  levels      " << levels.size() << "\n";
    for (std::size_t l = levels.size(); l-- > 0;) {
        const auto& L = levels[l];
        std::snprintf(buf, sizeof buf, "    level %2zu  %5u x %5u x %5u %s  %4u x %4u x %4u nodes  %10llu nodes  %5.1f%% empty  %s\n",
                      l, L.dims[0], L.dims[1], L.dims[2], reader.splitVoxels() ? "cells " : "voxels", L.nodes[0], L.nodes[1], L.nodes[2],
                      static_cast<unsigned long long>(L.nodeCount),
                      L.nodeCount ? 100.0 * double(L.emptyCount) / double(L.nodeCount) : 0.0,
                      bytes(double(L.payloadBytes)).c_str());
        o << buf;
    }
    std::snprintf(buf, sizeof buf, "  nodes       %llu (%.1f%% empty)\n", static_cast<unsigned long long>(nodeCount),
                  nodeCount ? 100.0 * double(emptyCount) / double(nodeCount) : 0.0);
    o << buf;
    const double ratio = h.payloadBytes ? double(rawBrickBytes) / double(h.payloadBytes) : 0.0;
    std::snprintf(buf, sizeof buf, "  compression %.2f : 1 (stored bricks %s -> %s)\n", ratio,
                  bytes(double(rawBrickBytes)).c_str(), bytes(double(h.payloadBytes)).c_str());
    o << buf;
    std::snprintf(buf, sizeof buf, "  on disk     %s (%.2f x the %s of voxel data)\n", bytes(double(fileBytes)).c_str(),
                  volumeBytes ? double(fileBytes) / double(volumeBytes) : 0.0, bytes(double(volumeBytes)).c_str());
    o << buf;
    return o.str();
}

}  // namespace hvx::core
