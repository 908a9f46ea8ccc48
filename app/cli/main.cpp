#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "app/cli/Commands.h"
#include "core/base/Error.h"

namespace {
const char* const kUsage =
        "holovox-cli — Holovox command line\n"
        "\n"
        "  build INPUT -o OUT.hvo [--brick N] [--border N] [--empty-below V] [--labels]\n"
        "        [--codec zstd|lz4|none] [--level N] [--lossy8] [--volume N]  (N: 1-based, 4D NIfTI or NRRD)\n"
        "        [--split-voxels [--split-n 2] [--split-overlap 2] [--split-threshold V]]  (thesis ch. 4)\n"
        "        [--dims XxYxZ --type uint8|int8|int16|uint16|int32|uint32|int64|uint64|float32|float64 --endian little|big\n"
        "         --header-bytes N --spacing SX,SY,SZ]            (raw input)\n"
        "      INPUT: .nii/.nii.gz, .nrrd/.nhdr, .mha/.mhd, .vtk, .vti, .raw, or phantom:XxYxZ[:seed];\n"
        "      a DICOM SEG (a label map), or an RTSTRUCT with --grid IMAGE.hvo (drawn onto its grid)\n"
        "  info FILE.hvo [--verify]      levels, nodes, empty fraction, compression, size\n"
        "  phantom --size XxYxZ -o OUT.{nrrd,hvo} [--seed N] [--noise HU]\n"
        "  demo [--input FILE] [-o OUT.hvo] [--no-pacs]   build the demo octree (MRI template) and\n"
        "        start the demo archive (local Orthanc with demo studies, default node 'demo')\n"        "  demo --status | --stop        whether the demo archive runs (exit 3 when not) | stop it\n"
        "  import PATH... [--db FILE] [--build]   scan folders/DICOMDIR/files into the study database\n"
        "  studies [--db FILE] [--patient TEXT] [--from YYYYMMDD] [--to YYYYMMDD] [--modality CT]\n"
        "  prune [--db FILE]             remove the rows of deleted files (unreachable folders are kept)\n"
        "  remove-study STUDY_UID [--db FILE] [--storage DIR]   forget a study; delete its received files\n"
        "        and octrees (files imported from your folders are kept)\n"
        "  build-series SERIES_UID -o OUT.hvo [--db FILE] [--volume N]   (N as import numbers them)\n"
        "        [--grid IMAGE.hvo]   an RT Structure Set series, drawn onto that image's grid\n"
        "  export-dicom INPUT -o FOLDER [--syntax explicit-little|implicit-little|explicit-big|deflate|rle|\n"
        "        jpeg-lossless|jpeg-ls] [--enhanced] [--modality CT|MR|PT|NM|OT] [--patient NAME] [--patient-id ID] [--study TEXT]\n"
        "  export-dicom --series-uid UID [--db FILE] [--volume N] -o FOLDER   (keeps patient, study, frame of reference)\n"
        "  pacs nodes | add NAME --ae AE --host H --port P [--move] [--default] [--max-pdu BYTES]\n"
        "        [--tls --tls-ca CA.pem [--tls-cert C.pem --tls-key K.pem]]\n"
        "  pacs add NAME --dicomweb URL [--token T | --user U --password P] [--insecure] [--default]\n"
        "  pacs echo NODE\n"
        "  pacs find NODE [--patient P] [--id I] [--date D|D1-D2] [--modality M] [--accession A]\n"
        "        [--level study|series|image] [--study UID] [--limit N]\n"
        "  pacs get|move NODE STUDY_UID [SERIES_UID] [--db FILE] [--no-build] [--parallel N]\n"
        "  pacs send NODE FILE... [--parallel N]   C-STORE (STOW-RS for a DICOMweb node) files to a node\n"
        "  listen [--port N] [--bind ADDR] [--ae AE] [--storage DIR] [--allow AE]   storage SCP in the foreground\n"
        "  dicom-info FILE               one-line summary of a DICOM file's header\n"
        "  render FILE.hvo [--cpu] [--view AZ,EL,ZOOM] [--mode dvr|iso|mip|minip|xray] [--tf PRESET]\n"
        "        [--boundary 0..1] [--view-transparency 0..1] [--unsharp 0..8] [--exaggerated 0..1] [--tools TOOLS.json]\n"
        "        [--iso HU] [--size WxH] [--budget BRICKS] [--accuracy VOXELS_PER_PIXEL] -o OUT.png|OUT.exr\n"
        "        [--multilevel]   where bricks of different levels meet, blend levels (up to two coarser): no seam\n"
        "        [--refraction N | V:N,...]   rays bend by Snell's law: what the transfer function shows\n"
        "        refracts with index N (air with 1), or the index is N at value V (physical units)\n"
        "        [--lut FILE] [--label-opacity A]   a label map: each label in its table's colour, never\n"
        "        blended (the table beside the octree, else generated colours)\n"
        "  lightfield FILE.hvo --display PROFILE -o OUT [--format quilt|projectors|exr|stereo|dvi] [--eta 0..1]\n"
        "        [--view AZ,EL] [--zoom Z] [--size WxH] [--observer X,Y,Z --simulate OUT.png] [--correction FILE.json]\n"
        "        [--refraction N | V:N,...] [--multilevel] [--cpu] | --list\n"
        "  measure FILE.hvo --roi sphere:X,Y,Z,R | box:X0,Y0,Z0,X1,Y1,Z1 | disc:X,Y,Z,NX,NY,NZ,R,T |\n"
        "        ellipse:X,Y,Z,NX,NY,NZ,AX,AY,AZ,A,B,T   voxels, mean, SD, min, max and volume of a region\n"
        "        (LPS mm), from the full-resolution level, in HU for CT\n"
        "  label-stats IMAGE.hvo LABELS.hvo [--lut FILE] [--force-frame] [-o OUT.csv]\n"
        "        each label's volume (mL) and the image's mean, SD, min, max at its voxels, as CSV\n"
        "  slice FILE.hvo --plane axial|coronal|sagittal|NX,NY,NZ [--at X,Y,Z] [--size WxH] [--pixel MM]\n"
        "        [--slab MM --slab-mode mip|minip|mean] [--window W,L] [--level N] [--scroll N] -o OUT.png\n"
        "        [--overlay B.hvo[:lut=hot|rainbow|pet|cool|grey|FILE,opacity=A,window=W/L]]\n"
        "        [--labels L.hvo [--lut FILE] [--label-opacity A] [--no-outline|--outline-only]] [--force-frame]\n"
        "        a windowed slice (--scroll: N slices a slice apart, timed, the last written); a second\n"
        "        volume laid over it in colour and/or a label map's fill and outlines (same frame of reference)\n"
        "  gl-info                       create a headless OpenGL 4.5 context and describe it\n"
        "  version                       versions of Holovox and its libraries";

void usage() { std::puts(kUsage); }

/// The lines of the usage that describe `cmd` (a line naming it and the indented lines that
/// continue it); empty for an unknown command.
std::string commandUsage(const std::string& cmd) {
    std::string out, line;
    bool in = false;
    for (const char* c = kUsage;; ++c) {
        if (*c != '\n' && *c != '\0') {
            line += *c;
            continue;
        }
        const bool head = line.rfind("  " + cmd + " ", 0) == 0 || line == "  " + cmd;
        const bool continued = line.rfind("      ", 0) == 0;
        if (head) in = true;
        else if (!continued) in = false;
        if (in) out += line + "\n";
        line.clear();
        if (*c == '\0') break;
    }
    return out;
}
}  // namespace

int main(int argc, char** argv) {
    if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help")) {
        usage();
        return argc < 2 ? 2 : 0;
    }
    const std::string cmd = argv[1];
    // COMMAND --help (or -h) anywhere after the command: that command's usage, and nothing run.
    for (int i = 2; i < argc; ++i)
        if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
            const std::string text = commandUsage(cmd);
            if (text.empty()) {
                std::fprintf(stderr, "holovox-cli: unknown command '%s' (try --help)\n", cmd.c_str());
                return 2;
            }
            std::printf("usage: holovox-cli\n%s", text.c_str());
            return 0;
        }
    try {
        if (cmd == "build") return hvx::app::buildCommand(argc, argv);
        if (cmd == "info") return hvx::app::infoCommand(argc, argv);
        if (cmd == "phantom") return hvx::app::phantomCommand(argc, argv);
        if (cmd == "demo") return hvx::app::demoCommand(argc, argv);
        if (cmd == "dicom-info") return hvx::app::dicomInfoCommand(argc, argv);
        if (cmd == "gl-info") return hvx::app::glInfoCommand(argc, argv);
        if (cmd == "import") return hvx::app::importCommand(argc, argv);
        if (cmd == "studies") return hvx::app::studiesCommand(argc, argv);
        if (cmd == "prune") return hvx::app::pruneCommand(argc, argv);
        if (cmd == "remove-study") return hvx::app::removeStudyCommand(argc, argv);
        if (cmd == "build-series") return hvx::app::buildSeriesCommand(argc, argv);
        if (cmd == "export-dicom") return hvx::app::exportDicomCommand(argc, argv);
        if (cmd == "pacs") return hvx::app::pacsCommand(argc, argv);
        if (cmd == "listen") return hvx::app::listenCommand(argc, argv);
        if (cmd == "render") return hvx::app::renderCommand(argc, argv);
        if (cmd == "lightfield") return hvx::app::lightFieldCommand(argc, argv);
        if (cmd == "measure") return hvx::app::measureCommand(argc, argv);
        if (cmd == "label-stats") return hvx::app::labelStatsCommand(argc, argv);
        if (cmd == "slice") return hvx::app::sliceCommand(argc, argv);
        if (cmd == "version" || cmd == "--version") return hvx::app::versionCommand(argc, argv);
        std::fprintf(stderr, "holovox-cli: unknown command '%s' (try --help)\n", cmd.c_str());
        return 2;
    } catch (const hvx::core::Cancelled&) {
        std::fprintf(stderr, "\nholovox-cli: cancelled; no output was written\n");
        return 130;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "holovox-cli: error: %s\n", e.what());
        return 1;
    }
}
