#include <chrono>
#include <cstdio>

#include "app/cli/CliArgs.h"
#include "app/cli/Commands.h"
#include "core/base/Error.h"
#include "core/octree/OctreeReader.h"
#include "core/reference/RegionStatistics.h"

namespace hvx::app {

int measureCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2, {"roi"}, {});
    if (args.positional().size() != 1 || !args.value("roi"))
        throw core::Error("usage: holovox-cli measure FILE.hvo --roi sphere:X,Y,Z,R | box:X0,Y0,Z0,X1,Y1,Z1 | "
                          "disc:X,Y,Z,NX,NY,NZ,R,T | ellipse:X,Y,Z,NX,NY,NZ,AX,AY,AZ,A,B,T  (LPS mm)");
    const auto reader = core::OctreeReader::open(args.positional()[0]);
    const auto region = core::MeasureRegion::parse(*args.value("roi"));
    const auto start = std::chrono::steady_clock::now();
    const auto s = core::RegionStatistics::compute(*reader, region);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const char* u = s.units.empty() ? "" : s.units.c_str();
    std::printf("%s, level 0 (full resolution)\n", region.describe().c_str());
    std::printf("  voxels  %llu\n", static_cast<unsigned long long>(s.voxels));
    if (s.voxels) {
        std::printf("  mean    %.6g %s\n  sd      %.6g %s\n  min     %.6g %s\n  max     %.6g %s\n", s.mean, u, s.sd, u,
                    s.min, u, s.max, u);
        if (s.areaMm2 > 0) std::printf("  area    %.6g mm2 (a region drawn on a slice)\n", s.areaMm2);
        std::printf("  volume  %.6g mm3 (%.6g ml)\n", s.volumeMm3, s.volumeMm3 / 1000.0);
    }
    if (!s.note.empty()) std::printf("  note    %s\n", s.note.c_str());
    std::printf("  time    %.1f ms\n", ms);
    return 0;
}

}  // namespace hvx::app
