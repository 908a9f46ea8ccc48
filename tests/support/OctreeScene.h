#pragma once
// A volume built into an octree in a temporary directory, with its brick cache, loader and an
// unculled working set: the common setup of the rendering tests.
#include <memory>

#include <glm/vec3.hpp>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/base/JobContext.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/volume/VoxelSource.h"
#include "core/streaming/WorkingSet.h"
#include "tests/support/TempDir.h"

namespace hvx::test {

struct OctreeScene {
    TempDir dir;
    std::unique_ptr<core::OctreeReader> reader;
    std::unique_ptr<core::BrickCache> cache;
    std::unique_ptr<core::BrickLoader> loader;
    std::unique_ptr<core::WorkingSet> ws;

    explicit OctreeScene(core::VoxelSource& source, const core::BuildOptions& options = {}) {
        core::JobContext job;
        core::OctreeBuilder(options).build(source, dir.file("v.hvo"), job);
        reader = core::OctreeReader::open(dir.file("v.hvo"));
        cache = std::make_unique<core::BrickCache>(1u << 28);
        loader = std::make_unique<core::BrickLoader>(*reader, *cache);
        core::WorkingSetOptions opt;
        opt.cullByTransferFunction = false;
        ws = std::make_unique<core::WorkingSet>(*reader, *cache, *loader, opt);
    }
    /// The volume's centre in patient coordinates.
    glm::dvec3 centre() const { return ws->space().centre(); }
};

}  // namespace hvx::test
