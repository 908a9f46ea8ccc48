// holovox-lightfield-mpi: the views of one light-field frame split across MPI ranks (thesis
// ch. 5: a 35-megapixel display driven by a cluster). Rank r draws views r, r + size, ...
// with its own brick cache and working set (refined for its views with the display's s(z));
// then rank 0 gathers every view and writes them all, or (--each) each rank writes its own.
//
//   mpirun -np 4 holovox-lightfield-mpi FILE.hvo --display holovizio-72 -o OUT_DIR [--each] [--cpu] [--size WxH]
#include <mpi.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/camera/DisplayModel.h"
#include "core/base/Error.h"
#include "core/image/ImageWriter.h"
#include "core/streaming/OctreeSpace.h"
#include "core/streaming/ContentBox.h"
#include "core/streaming/WorkingSet.h"
#include "render/EglOffscreenContext.h"
#include "render/LightFieldRenderer.h"

using namespace hvx;

namespace {
std::string viewFile(const std::string& dir, int i) {
    char name[48];
    std::snprintf(name, sizeof name, "view_%03d.png", i);
    return (std::filesystem::path(dir) / name).string();
}

int run(int rank, int size, int argc, char** argv) {
    std::string input, profile = "holovizio-72", out;
    bool each = false, cpu = false;
    int width = 0, height = 0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--display" && i + 1 < argc) profile = argv[++i];
        else if (a == "-o" && i + 1 < argc) out = argv[++i];
        else if (a == "--size" && i + 1 < argc) std::sscanf(argv[++i], "%dx%d", &width, &height);
        else if (a == "--each") each = true;
        else if (a == "--cpu") cpu = true;
        else if (input.empty() && a[0] != '-') input = a;
        else throw core::Error("unknown argument " + a);
    }
    if (input.empty() || out.empty())
        throw core::Error("usage: mpirun -np N holovox-lightfield-mpi FILE.hvo --display PROFILE -o OUT_DIR [--each] [--cpu] [--size WxH]");
    const auto display = core::DisplayModel::load(profile);
    const auto reader = core::OctreeReader::open(input);
    const auto& g = reader->geometry();
    const auto space = core::OctreeSpace::of(g, reader->brickSize(), reader->levelCount());
    const auto tf = core::TransferFunction::preset(g.hounsfield() ? "ct-bone" : "mr-default", g.valueMin, g.valueMax,
                                                   g.rescaleSlope, g.rescaleIntercept, space.minSpacing);
    // The anterior view, framed as `holovox-cli lightfield` frames it (core::ContentBox::framing).
    const auto framing = core::ContentBox::framing(display, *reader, tf, false, {1, 0, 0}, {0, 0, 1}, false);
    const double scale = framing.scale, depthScale = framing.depthScale;
    const auto all = display.views(framing.centre, {1, 0, 0}, {0, 0, 1}, 1.0, width, height, scale, depthScale);
    std::vector<core::View> mine;
    std::vector<int> ids;
    for (int i = rank; i < int(all.size()); i += size) {
        mine.push_back(all[std::size_t(i)]);
        ids.push_back(i);
    }
    core::WorkingSetOptions options;
    options.cpuMirror = cpu;
    options.maxBricks = 8192;
    core::BrickCache cache(1ull << 30);
    core::BrickLoader loader(*reader, cache);
    core::WorkingSet ws(*reader, cache, loader, options);
    std::unique_ptr<render::EglOffscreenContext> ctx;
    std::unique_ptr<render::GpuRayCaster> gpu;
    if (!cpu) {
        ctx = std::make_unique<render::EglOffscreenContext>();
        gpu = std::make_unique<render::GpuRayCaster>();
    }
    render::LightFieldRenderer::Stats stats;
    std::vector<core::RenderImage> images;
    if (!mine.empty())
        images = render::LightFieldRenderer::render(*reader, ws, loader, tf, {}, mine, display.accuracyFunction(scale, depthScale),
                                                    gpu.get(), true, &stats);
    std::printf("rank %d/%d: %zu views, cut of %zu bricks, %.0f ms ray casting\n", rank, size, images.size(),
                stats.cutNodes, stats.renderMs);
    std::filesystem::create_directories(out);
    if (each) {
        for (std::size_t k = 0; k < images.size(); ++k) core::ImageWriter::write(images[k], viewFile(out, ids[k]));
        return 0;
    }
    // Gather to rank 0: every view's RGBA floats, in view order.
    const int w = all[0].width, h = all[0].height;
    const int perView = w * h * 4;
    std::vector<float> sendBuffer;
    for (const auto& im : images)
        for (const auto& p : im.rgba) sendBuffer.insert(sendBuffer.end(), {p.r, p.g, p.b, p.a});
    std::vector<int> counts(static_cast<std::size_t>(size)), offsets(static_cast<std::size_t>(size));
    for (int r = 0; r < size; ++r) {
        int n = 0;
        for (int i = r; i < int(all.size()); i += size) ++n;
        counts[std::size_t(r)] = n * perView;
        offsets[std::size_t(r)] = r == 0 ? 0 : offsets[std::size_t(r - 1)] + counts[std::size_t(r - 1)];
    }
    std::vector<float> gathered(rank == 0 ? std::size_t(all.size()) * std::size_t(perView) : 0);
    MPI_Gatherv(sendBuffer.data(), int(sendBuffer.size()), MPI_FLOAT, gathered.data(), counts.data(), offsets.data(),
                MPI_FLOAT, 0, MPI_COMM_WORLD);
    if (rank != 0) return 0;
    for (int r = 0; r < size; ++r) {
        int k = 0;
        for (int i = r; i < int(all.size()); i += size, ++k) {
            core::RenderImage im;
            im.width = w;
            im.height = h;
            im.rgba.resize(std::size_t(w) * std::size_t(h));
            im.depth.assign(im.rgba.size(), 0.0f);
            const float* src = gathered.data() + offsets[std::size_t(r)] + std::size_t(k) * std::size_t(perView);
            std::memcpy(im.rgba.data(), src, std::size_t(perView) * sizeof(float));
            core::ImageWriter::write(im, viewFile(out, i));
        }
    }
    std::printf("rank 0 gathered %zu views of %dx%d into %s\n", all.size(), w, h, out.c_str());
    return 0;
}
}  // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    int rc = 0;
    try {
        rc = run(rank, size, argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "holovox-lightfield-mpi (rank %d): error: %s\n", rank, e.what());
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    MPI_Finalize();
    return rc;
}
