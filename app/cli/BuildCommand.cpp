#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "app/cli/CliArgs.h"
#include "app/cli/Commands.h"
#include "app/cli/OctreeBuildRunner.h"
#include "core/octree/BrickCodec.h"
#include "core/base/Error.h"
#include "core/base/AtomicFileWriter.h"
#include "core/volume/VoxelSourceFactory.h"
#include "core/octree/OctreeReader.h"
#include "core/octree/OctreeVoxelSource.h"
#include "core/appearance/LabelTable.h"
#include "dicom/SegmentationSource.h"
#include "dicom/StructureSetSource.h"

namespace hvx::app {

namespace {
glm::dvec3 parseSpacing(const std::string& text) {
    glm::dvec3 s;
    char c1 = 0, c2 = 0;
    std::istringstream in(text);
    if (!(in >> s.x >> c1 >> s.y >> c2 >> s.z) || c1 != ',' || c2 != ',' || !(s.x > 0 && s.y > 0 && s.z > 0))
        throw core::Error("--spacing must be three positive numbers like 0.5,0.5,1.25");
    return s;
}
}  // namespace

int buildCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2,
                       {"o", "output", "brick", "border", "empty-below", "codec", "level", "dims", "type", "endian",
                        "header-bytes", "spacing", "volume", "grid", "split-n", "split-overlap", "split-threshold", "modality"},
                       {"labels", "lossy8", "quiet", "split-voxels"});
    if (args.positional().size() != 1) throw core::Error("usage: holovox-cli build INPUT -o OUT.hvo [options]");
    const auto out = args.value("o") ? args.value("o") : args.value("output");
    if (!out) throw core::Error("build needs an output file: -o OUT.hvo");

    core::RawVoxelSource::Options raw;
    if (const auto d = args.value("dims")) raw.dims = core::VoxelSourceFactory::parseDims(*d);
    if (const auto t = args.value("type")) raw.element = core::parseFileElement(*t);
    if (const auto e = args.value("endian")) {
        if (*e != "little" && *e != "big") throw core::Error("--endian must be little or big");
        raw.bigEndian = *e == "big";
    }
    raw.headerBytes = std::uint64_t(args.integer("header-bytes", 0, 0, 1L << 40));
    if (const auto s = args.value("spacing")) {
        raw.spacing = parseSpacing(*s);
        raw.spacingAssumed = false;
    }
    const std::string input = args.positional()[0];
    raw.warnings.push_back(input + ": a raw file holds no orientation: its axes are taken as L, P and S, and the views draw \"?\" for them");
    if (raw.spacingAssumed) raw.warnings.push_back(input + ": no --spacing for a raw file: 1 mm assumed, lengths are not millimetres");
    if (const auto w = core::conversionWarning(raw.element); !w.empty()) raw.warnings.push_back(input + ": " + w);

    core::BuildOptions opt;
    opt.brickSize = std::uint32_t(args.integer("brick", 32, 4, 256));
    opt.border = std::uint32_t(args.integer("border", 2, 1, 8));
    opt.emptyBelow = args.number("empty-below");
    opt.labels = args.flag("labels");
    opt.lossy8 = args.flag("lossy8");
    if (const auto c = args.value("codec")) opt.codec = core::BrickCodec::parse(*c);
    opt.codecLevel = int(args.integer("level", 0, -7, 19));

    const auto volume = std::uint32_t(args.integer("volume", 1, 1, 1 << 20) - 1);  // 1-based on the command line
    // A DICOM Segmentation object is a label map, with its segments' names and colours kept
    // beside the octree as a colour table.
    std::unique_ptr<dicom::SegmentationSource> seg;
    if (dicom::SegmentationSource::isSegmentation(args.positional()[0])) {
        seg = std::make_unique<dicom::SegmentationSource>(args.positional()[0]);
        opt.labels = true;
    }
    // An RT Structure Set is contours: drawn onto the grid of the image it is shown over.
    std::unique_ptr<dicom::StructureSetSource> rt;
    if (!seg && dicom::StructureSetSource::isStructureSet(args.positional()[0])) {
        const auto grid = args.value("grid");
        if (!grid)
            throw core::Error(args.positional()[0] + " is an RT Structure Set (contours): give the image octree "
                              "whose grid it is drawn onto, --grid IMAGE.hvo");
        rt = std::make_unique<dicom::StructureSetSource>(args.positional()[0], core::OctreeReader::open(*grid)->geometry());
        opt.labels = true;
    } else if (args.value("grid")) {
        throw core::Error("--grid is for RT Structure Sets, which are drawn onto an image's grid");
    }
    // An octree: its full-resolution level read back exactly (a split-voxel octree of a volume
    // already built, without its original files).
    const bool fromOctree = std::filesystem::path(args.positional()[0]).extension() == ".hvo";
    std::unique_ptr<core::VoxelSource> source =
        seg          ? std::unique_ptr<core::VoxelSource>(std::move(seg))
        : rt         ? std::unique_ptr<core::VoxelSource>(std::move(rt))
        : fromOctree ? std::make_unique<core::OctreeVoxelSource>(core::OctreeReader::open(args.positional()[0]))
                     : core::VoxelSourceFactory::open(args.positional()[0], raw, volume);
    for (const auto& w : source->warnings()) std::fprintf(stderr, "holovox-cli: warning: %s\n", w.c_str());
    // --modality says what a file does not (a NIfTI, NRRD or raw file is "OT"); it never
    // overrides a modality the source names.
    if (const auto m = args.value("modality")) {
        if (!core::VolumeGeometry::isModalityCode(*m)) throw core::Error("--modality " + *m + " is not a DICOM modality code (CT, MR, PT, ...)");
        const std::string& named = source->geometry().modality;
        if (!named.empty() && named != "OT" && named != *m)
            throw core::Error("--modality " + *m + ": " + args.positional()[0] + " says it is " + named);
        opt.modality = *m;
    }
    // Split-voxels (thesis ch. 4): two values and a plane per cell of N³ voxels, for sharp
    // boundaries and true colours at coarse levels; a file beside the volume's own octree.
    std::optional<core::SplitVoxelOptions> split;
    if (args.flag("split-voxels")) {
        split.emplace();
        split->n = std::uint32_t(args.integer("split-n", 2, 0, 1 << 20));
        split->overlap = std::uint32_t(args.integer("split-overlap", 2, 0, 1 << 20));
        split->labels = opt.labels || source->geometry().isLabel;
        const auto& g = source->geometry();
        if (const auto t = args.number("split-threshold")) {
            // Physical units (HU for CT) on the command line; stored units inside.
            if (!std::isfinite(*t) || *t < 0)
                throw core::Error("--split-threshold must be a value of 0 or more, in the volume's units (HU for CT)");
            split->threshold = std::abs(*t / g.rescaleSlope);
        }  // without one: 2% of the stored range found in the volume, so noise in one material stays one value
        split->validate();
    } else if (args.value("split-n") || args.value("split-overlap") || args.value("split-threshold")) {
        throw core::Error("--split-n, --split-overlap and --split-threshold go with --split-voxels");
    }
    OctreeBuildRunner::run(*source, *out, opt, !args.flag("quiet"), split);
    const core::LabelTable* names = nullptr;
    if (const auto* segmentation = dynamic_cast<const dicom::SegmentationSource*>(source.get())) names = &segmentation->table();
    if (const auto* structures = dynamic_cast<const dicom::StructureSetSource*>(source.get())) names = &structures->table();
    // A label map's names and colours follow it from octree to octree.
    const std::string sidecar = core::LabelTable::sidecarPath(args.positional()[0]);
    if (fromOctree && std::filesystem::exists(sidecar)) {
        std::error_code ec;
        std::filesystem::copy_file(sidecar, core::LabelTable::sidecarPath(*out), std::filesystem::copy_options::overwrite_existing, ec);
        if (ec) throw core::Error(core::LabelTable::sidecarPath(*out) + ": cannot be written (" + ec.message() + ")");
    }
    if (names) {
        const std::string table = names->toSlicerTable(), path = core::LabelTable::sidecarPath(*out);
        core::AtomicFileWriter w(path);
        w.append(table.data(), table.size());
        w.commit();
        std::fprintf(stderr, "labels' names and colours: %s\n", path.c_str());
    }
    return 0;
}

}  // namespace hvx::app
