#include "core/octree/OctreeBuilder.h"
#include "core/octree/HvoHeader.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <future>
#include <limits>
#include <mutex>

#include "core/base/AtomicFileWriter.h"
#include "core/octree/BrickCodec.h"
#include "core/base/Error.h"
#include "core/octree/LevelSlices.h"
#include "core/octree/OctreeLayout.h"
#include "core/base/Memory.h"
#include "core/base/ThreadPool.h"

namespace hvx::core {

namespace {

struct EncodedBrick {
    std::uint32_t node = 0;
    float minValue = 0, maxValue = 0;
    float quantMin = 0, quantMax = 0;
    bool empty = false;
    std::vector<std::byte> payload;
    double sqError = 0.0;
    double maxError = 0.0;
    std::uint64_t errorSamples = 0;
};

template <class T>
class BuildRun {
public:
    BuildRun(const BuildOptions& opt, VoxelSource& source, const OctreeLayout& layout,
             std::vector<hvo::NodeRecord>& nodes, AtomicFileWriter& out, JobContext& job)
        : opt_(opt), source_(source), layout_(layout), nodes_(nodes), out_(out), job_(job),
          edge_(opt.brickSize + 2 * opt.border) {
        for (int l = 0; l < layout.levelCount(); ++l)
            levels_.emplace_back(layout.levelDims(l), opt.brickSize, opt.border);
        nextRow_.assign(std::size_t(layout.levelCount()), 0);
        const auto& g = source.geometry();
        if (opt.emptyBelow) {
            // Physical threshold -> stored units (the rescale may be decreasing).
            emptyStored_ = (*opt.emptyBelow - g.rescaleIntercept) / g.rescaleSlope;
            if (g.rescaleSlope < 0) emptyStored_ = -std::numeric_limits<double>::infinity();
        }
    }

    void run() {
        const auto& dims = source_.geometry().dims;
        // Small read-ahead slabs: enough to overlap I/O, little memory (8 slices of 2048^2 int16 = 64 MiB).
        const std::uint32_t slab = 8;
        auto readSlab = [this, &dims, slab](std::uint32_t z0) {
            const std::uint32_t n = std::min(slab, dims[2] - z0);
            std::vector<std::vector<T>> slices;
            for (std::uint32_t s = 0; s < n; ++s) {
                slices.push_back(levels_[0].takeBuffer());
                source_.readSlices(z0 + s, 1, slices.back().data());
            }
            return slices;
        };
        std::future<std::vector<std::vector<T>>> next = std::async(std::launch::async, readSlab, 0u);
        for (std::uint32_t z0 = 0; z0 < dims[2]; z0 += slab) {
            auto slices = next.get();
            job_.throwIfCancelled();
            if (z0 + slab < dims[2]) next = std::async(std::launch::async, readSlab, z0 + slab);
            for (auto& s : slices) pushSlice(0, std::move(s));
            job_.report(double(std::min(dims[2], z0 + slab)) / dims[2], "building");
        }
    }

    double sqError = 0.0, maxError = 0.0;
    std::uint64_t errorSamples = 0, emptyNodes = 0, rawBytes = 0, payloadBytes = 0;

private:
    void pushSlice(int level, std::vector<T> slice) {
        auto& lv = levels_[std::size_t(level)];
        const std::uint32_t z = lv.received();
        lv.push(std::move(slice));
        std::vector<T> down;
        const bool hasParent = level + 1 < layout_.levelCount();
        if (hasParent && (z % 2 == 1 || z + 1 == lv.dims()[2])) {
            const T* a = lv.slice(z % 2 == 1 ? z - 1 : z);
            const T* b = lv.slice(z);
            const std::uint32_t w = lv.dims()[0], h = lv.dims()[1];
            const std::uint32_t h2 = (h + 1) / 2, w2 = (w + 1) / 2;
            down.resize(std::size_t(w2) * h2);
            ThreadPool::shared().parallelFor(h2, [&](std::size_t y0, std::size_t y1) {
                for (std::size_t y = y0; y < y1; ++y) {
                    const std::size_t r0 = 2 * y * w, r1 = std::min<std::size_t>(2 * y + 1, h - 1) * w;
                    LevelSlices<T>::downsampleRow(a + r0, a + r1, b + r0, b + r1, w, down.data() + y * w2,
                                                  opt_.labels);
                }
            }, 16);
        }
        emitReadyRows(level);
        if (!down.empty()) pushSlice(level + 1, std::move(down));
    }

    void emitReadyRows(int level) {
        auto& lv = levels_[std::size_t(level)];
        auto& row = nextRow_[std::size_t(level)];
        while (row < lv.rows() && lv.rowReady(row)) {
            emitRow(level, row);
            ++row;
            lv.dropBefore(row);
        }
    }

    void emitRow(int level, std::uint32_t row) {
        const auto& n = layout_.levelNodes(level);
        const std::size_t count = std::size_t(n[0]) * n[1];
        job_.throwIfCancelled();
        ThreadPool::shared().parallelFor(count, [&](std::size_t s, std::size_t e) {
            thread_local std::vector<T> brick;
            brick.resize(std::size_t(edge_) * edge_ * edge_);
            EncodedBrick eb;
            for (std::size_t c = s; c < e; ++c) {
                job_.throwIfCancelled();
                eb = EncodedBrick{};
                encode(level, std::uint32_t(c % n[0]), std::uint32_t(c / n[0]), row, brick, eb);
                // Writing under the lock overlaps other workers' compression.
                std::lock_guard lock(storeMutex_);
                store(eb);
            }
        });
    }

    void encode(int level, std::uint32_t x, std::uint32_t y, std::uint32_t row, std::vector<T>& brick,
                EncodedBrick& eb) const {
        eb.node = layout_.nodeId(level, x, y, row);
        levels_[std::size_t(level)].extractBrick(x, y, row, brick.data());
        T mn = brick[0], mx = brick[0];
        for (const T v : brick) {  // plain loop: vectorises, unlike minmax_element
            mn = v < mn ? v : mn;
            mx = v > mx ? v : mx;
        }
        eb.quantMin = float(mn);
        eb.quantMax = float(mx);
        eb.minValue = eb.quantMin;
        eb.maxValue = eb.quantMax;
        // The node's range covers its descendants, which were all emitted before it.
        const auto& rec = nodes_[eb.node];
        if (rec.childMask) {
            for (std::uint32_t c = 0, o = 0; o < 8; ++o) {
                if (!(rec.childMask & (1u << o))) continue;
                const auto& child = nodes_[rec.firstChild + c++];
                eb.minValue = std::min(eb.minValue, child.minValue);
                eb.maxValue = std::max(eb.maxValue, child.maxValue);
            }
        }
        if (opt_.emptyBelow && double(eb.maxValue) < emptyStored_) {
            eb.empty = true;
            return;
        }
        if (opt_.lossy8) {
            std::vector<std::uint8_t> q(brick.size());
            const double lo = eb.quantMin, range = double(eb.quantMax) - lo;
            const double scale = range > 0 ? 255.0 / range : 0.0;
            for (std::size_t i = 0; i < brick.size(); ++i)
                q[i] = std::uint8_t(std::lround((double(brick[i]) - lo) * scale));
            if (level == 0) measureLossyError(brick, q, lo, range, eb);
            BrickCodec::compress(opt_.codec, q.data(), q.size(), eb.payload, opt_.codecLevel);
        } else {
            BrickCodec::compress(opt_.codec, brick.data(), brick.size() * sizeof(T), eb.payload, opt_.codecLevel,
                                 sizeof(T));
        }
    }

    void measureLossyError(const std::vector<T>& brick, const std::vector<std::uint8_t>& q, double lo, double range,
                           EncodedBrick& eb) const {
        const std::uint32_t b = opt_.border, e = edge_;
        for (std::uint32_t z = b; z < e - b; ++z)
            for (std::uint32_t y = b; y < e - b; ++y)
                for (std::uint32_t x = b; x < e - b; ++x) {
                    const std::size_t i = (std::size_t(z) * e + y) * e + x;
                    const double back = lo + q[i] * (range / 255.0);
                    const double err = std::abs(back - double(brick[i]));
                    eb.sqError += err * err;
                    eb.maxError = std::max(eb.maxError, err);
                    ++eb.errorSamples;
                }
    }

    void store(EncodedBrick& eb) {
        auto& rec = nodes_[eb.node];
        rec.minValue = eb.minValue;
        rec.maxValue = eb.maxValue;
        rec.quantMin = eb.quantMin;
        rec.quantMax = eb.quantMax;
        sqError += eb.sqError;
        maxError = std::max(maxError, eb.maxError);
        errorSamples += eb.errorSamples;
        if (eb.empty) {
            rec.flags |= hvo::NodeEmpty;
            ++emptyNodes;
            return;
        }
        if (opt_.lossy8) rec.flags |= hvo::NodeLossy8;
        rec.payloadSize = std::uint32_t(eb.payload.size());
        rec.checksum = BrickCodec::checksum(eb.payload.data(), eb.payload.size());
        rec.payloadOffset = out_.append(eb.payload.data(), eb.payload.size());
        payloadBytes += eb.payload.size();
        rawBytes += std::size_t(edge_) * edge_ * edge_ * (opt_.lossy8 ? 1 : sizeof(T));
        std::vector<std::byte>().swap(eb.payload);
    }

    const BuildOptions& opt_;
    VoxelSource& source_;
    const OctreeLayout& layout_;
    std::vector<hvo::NodeRecord>& nodes_;
    AtomicFileWriter& out_;
    JobContext& job_;
    std::uint32_t edge_;
    double emptyStored_ = 0.0;
    std::deque<LevelSlices<T>> levels_;  // deque: LevelSlices holds a mutex and must not move
    std::vector<std::uint32_t> nextRow_;
    std::mutex storeMutex_;
};

}  // namespace

namespace {
constexpr const char* kLabelsKeepEveryBrick =
    "a label map keeps every brick: --empty-below would drop whole labels without a word";
}  // namespace

OctreeBuilder::OctreeBuilder(BuildOptions options) : options_(std::move(options)) {
    if (options_.brickSize < 4 || options_.brickSize > 256)
        throw Error("brick size must be between 4 and 256 voxels");
    if (options_.border < 1 || options_.border > 8) throw Error("border must be between 1 and 8 voxels");
    if (options_.lossy8 && options_.labels) throw Error("label volumes cannot be stored lossy");
    if (options_.emptyBelow && options_.labels) throw Error(kLabelsKeepEveryBrick);
}

void OctreeBuilder::checkMemory(const VolumeGeometry& g, const std::string& name) const {
    // A build holds the node records twice (the layout's and the file's) with the layout's grid
    // tables, and at each level the slices a brick row needs with the read-ahead, each level's a
    // quarter of the one below: measured, 62 slices of 2048^2 int16 for bricks of 32 (this
    // estimate: 61), 94 for bricks of 64 (estimate 104).
    const auto counts = OctreeLayout::count(g.dims, options_.brickSize);
    if (counts.nodes == UINT64_MAX) return;  // the layout refuses it in words of its own
    const double sliceBytes = double(g.dims[0]) * double(g.dims[1]) * double(scalarSize(g.scalarType));
    const double slices = (double(options_.brickSize + 2 * options_.border) + 12.0) * 4.0 / 3.0;
    const double records = double(counts.nodes) * double(2 * sizeof(hvo::NodeRecord) + sizeof(std::uint32_t));
    const double held = sliceBytes * slices + records;
    const double memory = double(physicalMemoryBytes());
    if (held > memory)
        throw Error(name + ": building its octree would hold about " + gibibytes(held) + " at once (about " +
                    std::to_string(int(slices)) + " slices of " + gibibytes(sliceBytes) + ", and the records of " +
                    std::to_string(counts.nodes) + " bricks), more than this machine's " + gibibytes(memory) +
                    " of memory; Holovox builds a volume slice by slice, so its slices must be smaller");
}

BuildReport OctreeBuilder::build(VoxelSource& source, const std::string& output, JobContext& job) {
    const auto t0 = std::chrono::steady_clock::now();
    const VolumeGeometry& g = source.geometry();
    g.validate(source.describe());
    if (options_.lossy8 && g.scalarType == ScalarType::UInt8)
        throw Error(source.describe() + ": lossy 8-bit storage only applies to 16-bit and float volumes");
    if ((options_.labels || g.isLabel) && (g.rescaleSlope != 1.0 || g.rescaleIntercept != 0.0)) {
        char scale[96];
        std::snprintf(scale, sizeof scale, "%.9g * v + %.9g", g.rescaleSlope, g.rescaleIntercept);
        throw Error(source.describe() + ": a label map's classes are its stored values, but the file rescales them (" +
                    scale + "; ITK would read other labels): Holovox does not guess which are meant");
    }
    if (options_.emptyBelow && g.isLabel) throw Error(source.describe() + ": " + kLabelsKeepEveryBrick);
    checkMemory(g, source.describe());
    const OctreeLayout layout(g.dims, options_.brickSize);
    std::vector<hvo::NodeRecord> nodes = layout.nodes();
    AtomicFileWriter out(output);

    hvo::FileHeader header = hvo::startHeader(g, options_, layout.levelCount());
    out.append(&header, sizeof header);  // complete == 0 until the end

    BuildReport report;
    dispatchScalar(g.scalarType, [&](auto tag) {
        using T = decltype(tag);
        BuildOptions opt = options_;
        opt.labels = options_.labels || g.isLabel;
        BuildRun<T> run(opt, source, layout, nodes, out, job);
        run.run();
        report.emptyNodes = run.emptyNodes;
        header.payloadBytes = run.payloadBytes;
        header.rawBrickBytes = run.rawBytes;
        if (run.errorSamples) {
            header.lossyRmsError = std::sqrt(run.sqError / double(run.errorSamples));
            header.lossyMaxError = run.maxError;
        }
    });
    job.throwIfCancelled();
    // A label is a class: held as a 32-bit float (the type wide integer files are kept as), it
    // is exact only below 2^24 in magnitude, where two neighbouring classes would become one.
    const double largest = std::max(std::abs(double(nodes[0].minValue)), std::abs(double(nodes[0].maxValue)));
    if ((options_.labels || g.isLabel) && g.scalarType == ScalarType::Float32 && largest >= 16777216.0) {
        char value[48];
        std::snprintf(value, sizeof value, "%.0f", largest);
        throw Error(source.describe() + ": its labels reach " + value + " in magnitude; Holovox keeps labels exactly "
                    "only below 16777216 (2^24), and larger ones would merge or change: renumber the classes");
    }

    hvo::finishFile(header, nodes, out);

    report.nodeCount = nodes.size();
    report.fileBytes = header.fileSize;
    report.inputBytes = g.byteSize();
    report.lossyRmsError = header.lossyRmsError;
    report.lossyMaxError = header.lossyMaxError;
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    job.report(1.0, "done");
    return report;
}

}  // namespace hvx::core
