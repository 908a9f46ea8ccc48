// Writes small, valid .hvo files (every scalar type and codec, labels, lossy bricks) into a
// folder: the seed corpus of the .hvo fuzzer (tests/fuzz/run_fuzz.sh).
#include <cstdio>
#include <string>

#include "core/base/JobContext.h"
#include "core/octree/OctreeBuilder.h"
#include "core/volume/PhantomVoxelSource.h"

int main(int argc, char** argv) {
    using namespace hvx::core;
    if (argc != 2) {
        std::fprintf(stderr, "usage: hvo_seeds FOLDER\n");
        return 2;
    }
    int n = 0;
    for (auto codec : {hvo::Codec::Zstd, hvo::Codec::Lz4, hvo::Codec::None})
        for (int variant = 0; variant < 3; ++variant) {
            PhantomVoxelSource phantom({12u + 5u * std::uint32_t(variant), 10, 9}, std::uint64_t(variant + 1));
            BuildOptions o;
            o.brickSize = 4;
            o.border = 1;
            o.codec = codec;
            o.labels = variant == 1;
            o.lossy8 = variant == 2;
            JobContext job;
            OctreeBuilder(o).build(phantom, std::string(argv[1]) + "/seed" + std::to_string(n++) + ".hvo", job);
        }
    std::printf("%d seeds\n", n);
    return 0;
}
