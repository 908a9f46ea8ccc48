#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <set>

#include "app/cli/CliArgs.h"
#include "app/cli/Commands.h"
#include "core/octree/OctreeReader.h"
#include "app/cli/OctreeBuildRunner.h"
#include "app/cli/ProgressBar.h"
#include "app/cli/SignalCancel.h"
#include "core/base/Error.h"
#include "core/volume/RescaledInt16Source.h"
#include "core/volume/VoxelSourceFactory.h"
#include "dicom/DicomScanner.h"
#include "dicom/DicomSeriesSource.h"
#include "dicom/DicomSeriesWriter.h"
#include "dicom/SeriesAssembler.h"
#include "dicom/SegmentationSource.h"
#include "dicom/PacsSettings.h"
#include "dicom/SeriesOctree.h"
#include "dicom/StudyRemoval.h"
#include "dicom/StudyDatabase.h"
#include "dicom/UidPath.h"

namespace hvx::app {

namespace {
std::string octreeFolder(const std::string& dbPath) {
    return (std::filesystem::path(dbPath).parent_path() / "octrees").string();
}

/// One line per volume; `number` (1-based) is its place among the series' volumes, shown when
/// a series holds several (the N of build-series --volume N).
void printVolume(const dicom::SeriesVolume& v, std::size_t number = 0) {
    const auto& g = v.geometry;
    const std::string label = (number ? "#" + std::to_string(number) + " " : std::string()) + v.label;
    std::printf("    %-40s %4u x %4u x %4u  %.3g x %.3g x %.3g mm  %s%s\n", label.c_str(), g.dims[0], g.dims[1],
                g.dims[2], g.spacing.x, g.spacing.y, g.spacing.z, std::string(core::scalarName(g.scalarType)).c_str(),
                g.monochrome1 ? " MONOCHROME1" : "");
    for (const auto& w : v.warnings) std::printf("      warning: %s\n", w.c_str());
}

dicom::DicomScanner::Result scanFiles(const std::vector<std::string>& paths) {
    ProgressBar bar("scan ");
    core::JobContext job(bar.observer());
    SignalCancel cancel(job);
    auto scan = dicom::DicomScanner::scan(paths, job);
    bar.finish();
    return scan;
}

std::string octreeName(const dicom::SeriesVolume& v, std::size_t stacks, std::size_t index) {
    return dicom::UidPath::component(v.seriesUid) + (stacks > 1 ? "-stack" + std::to_string(index + 1) : "") + ".hvo";
}
}  // namespace

int importCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2, {"db"}, {"build"});
    if (args.positional().empty()) throw core::Error("usage: holovox-cli import PATH... [--db FILE] [--build]");
    const std::string dbPath = args.value("db").value_or(dicom::StudyDatabase::defaultPath());
    dicom::StudyDatabase db(dbPath);
    const auto scan = scanFiles(args.positional());
    const auto stats = db.addInstances(scan.instances);
    // What a UID collision refused is never stacked either.
    std::vector<std::string> notes = stats.conflicts;
    const auto accepted = stats.accepted(scan.instances);
    // The whole series' volumes where earlier imports brought more of it: listed and built.
    const auto volumes =
        dicom::SeriesOctree::recordVolumes(db, dicom::SeriesAssembler::assemble(accepted, notes), accepted);
    std::printf("scanned %zu files: %zu DICOM, %zu not DICOM (skipped), %zu broken\n", scan.filesSeen,
                scan.instances.size(), scan.notDicom, scan.broken);
    for (const auto& r : scan.brokenReasons) std::printf("  broken: %s\n", r.c_str());
    if (scan.setAside)
        std::printf("  not imported: %zu file(s) a receive set aside in its storage folder (.incoming: still being "
                    "received; .conflicts: refused on receipt)\n", scan.setAside);
    std::printf("database %s: %zu new, %zu already known, %zu moved\n", dbPath.c_str(), stats.added, stats.unchanged,
                stats.moved);
    for (const auto& n : notes) std::printf("  note: %s\n", n.c_str());
    // Patient -> study -> series table of what was found.
    std::string lastPatient, lastStudy;
    std::map<std::string, std::size_t> volumesPerSeries, volumeNumber;
    for (const auto& v : volumes) ++volumesPerSeries[v.seriesUid];
    for (const auto& v : volumes) {
        const auto& in = v.instances.front();
        if (in.patientId + in.patientName != lastPatient) {
            std::printf("patient %s (%s) born %s sex %s\n", in.patientName.c_str(), in.patientId.c_str(),
                        in.patientBirthDate.c_str(), in.patientSex.c_str());
            lastPatient = in.patientId + in.patientName;
            lastStudy.clear();
        }
        if (in.studyInstanceUid != lastStudy) {
            std::printf("  study %s %s \"%s\" accession %s\n", in.studyDate.c_str(), in.studyTime.c_str(),
                        in.studyDescription.c_str(), in.accessionNumber.c_str());
            lastStudy = in.studyInstanceUid;
        }
        printVolume(v, volumesPerSeries[v.seriesUid] > 1 ? ++volumeNumber[v.seriesUid] : 0);
    }
    if (args.flag("build")) {
        std::filesystem::create_directories(octreeFolder(dbPath));
        std::map<std::string, std::size_t> stacks, index;
        for (const auto& v : volumes) ++stacks[v.seriesUid];
        for (const auto& v : volumes) {
            const std::string out =
                (std::filesystem::path(octreeFolder(dbPath)) / octreeName(v, stacks[v.seriesUid], index[v.seriesUid]++))
                    .string();
            dicom::DicomSeriesSource source(v);
            OctreeBuildRunner::run(source, out, core::BuildOptions{}, false);
            dicom::SeriesOctree::record(db, v.seriesUid, out);  // deleted, and said, when removed meanwhile
        }
    }
    return scan.instances.empty() && scan.broken > 0 ? 1 : 0;
}

int pruneCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2, {"db"}, {});
    dicom::StudyDatabase db(args.value("db").value_or(dicom::StudyDatabase::defaultPath()));
    const auto r = db.prune();
    std::printf("removed %zu instances whose files were deleted\n", r.removed);
    if (r.kept)
        std::printf("kept %zu instances whose folders are missing (an unmounted or renamed storage folder?); "
                    "they come back online when the folder does\n",
                    r.kept);
    return 0;
}

int removeStudyCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2, {"db", "config", "storage"}, {});
    if (args.positional().size() != 1) throw core::Error("usage: holovox-cli remove-study STUDY_UID [--db FILE]");
    const std::string dbPath = args.value("db").value_or(dicom::StudyDatabase::defaultPath());
    const auto settings = dicom::PacsSettings::load(args.value("config").value_or(dicom::PacsSettings::defaultPath()));
    const std::string storage = args.value("storage").value_or(settings.local.storageDir);
    dicom::StudyDatabase db(dbPath);
    const std::string uid = args.positional()[0];
    const auto r = dicom::StudyRemoval::remove(db, uid, storage, dicom::SeriesOctree::folderFor(dbPath));
    std::printf("removed study %s of %s from the study database: %zu image(s)\n", uid.c_str(), r.patient.c_str(),
                r.forgotten);
    if (r.deleted) std::printf("deleted %zu received file(s) from %s\n", r.deleted, storage.c_str());
    if (r.kept) std::printf("kept %zu imported file(s) where they are (only Holovox's own storage is deleted)\n", r.kept);
    if (r.shared) {
        std::string who;
        for (const auto& s : r.sharers) who += (who.empty() ? "" : "; ") + s;
        std::printf("kept %zu received file(s) that another study database sharing %s indexes: %s\n", r.shared,
                    storage.c_str(), who.c_str());
    }
    if (r.octrees) std::printf("deleted %zu octree(s)\n", r.octrees);
    for (const auto& f : r.failed) std::fprintf(stderr, "could not delete %s\n", f.c_str());
    if (r.reindexed)
        std::fprintf(stderr, "indexed again: %zu received file(s) that could not be deleted; the study stays listed with "
                             "them (remove it again once they can be deleted)\n", r.reindexed);
    return r.failed.empty() ? 0 : 1;
}

int studiesCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2, {"db", "patient", "from", "to", "modality"}, {});
    dicom::StudyDatabase db(args.value("db").value_or(dicom::StudyDatabase::defaultPath()));
    const auto check = db.checkFiles();
    if (check.offline)
        std::printf("%zu instances are offline: their files cannot be reached now (kept in the index; "
                    "`holovox-cli prune` removes the rows of deleted files)\n",
                    check.offline);
    if (check.backOnline) std::printf("%zu instances are back online\n", check.backOnline);
    dicom::StudyQuery q;
    q.text = args.value("patient").value_or("");
    q.dateFrom = args.value("from").value_or("");
    q.dateTo = args.value("to").value_or("");
    q.modality = args.value("modality").value_or("");
    const auto studies = db.findStudies(q);
    for (const auto& s : studies) {
        std::printf("%-24s %-12s %s %-6s %-30s %s\n", s.patientName.c_str(), s.patientId.c_str(), s.date.c_str(),
                    s.modalities.c_str(), s.description.c_str(), s.studyUid.c_str());
        for (const auto& se : db.seriesOfStudy(s.studyUid)) {
            std::printf("    series %3d %-4s %-28s %4d images  %s%s%s\n", se.number, se.modality.c_str(),
                        se.description.c_str(), se.instanceCount, se.seriesUid.c_str(),
                        se.octreePath.empty() ? "" : "  octree: ", se.octreePath.c_str());
            for (const auto& w : se.warnings) std::printf("      warning: %s\n", w.c_str());
            for (const auto& v : db.volumesOfSeries(se.seriesUid))  // a 4D series' volumes
                std::printf("      #%d %s%s%s\n", v.number, v.varying.c_str(), v.octreePath.empty() ? "" : "  octree: ",
                            v.octreePath.c_str());
        }
    }
    std::printf("%zu studies\n", studies.size());
    return 0;
}

int buildSeriesCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2, {"db", "o", "output", "stack", "volume", "grid"}, {});
    const auto out = args.value("o") ? args.value("o") : args.value("output");
    if (args.positional().size() != 1 || !out)
        throw core::Error("usage: holovox-cli build-series SERIES_UID -o OUT.hvo [--db FILE] [--volume N] "
                          "[--grid IMAGE.hvo (RT Structure Sets)]");
    const std::string uid = args.positional()[0];
    dicom::StudyDatabase db(args.value("db").value_or(dicom::StudyDatabase::defaultPath()));
    const auto files = db.filesOfSeries(uid);
    if (files.empty()) throw core::Error("series " + uid + " is not in the database (import it first)");
    if (dicom::SegmentationSource::isSegmentation(files.front())) {  // a label map, with its colour table
        core::JobContext job;
        std::vector<std::string> warnings;
        const auto path = dicom::SeriesOctree::build(db, uid, job, &warnings, *out);
        for (const auto& w : warnings) std::fprintf(stderr, "holovox-cli: warning: %s\n", w.c_str());
        std::printf("segmentation %s: label map %s, segments' names and colours in %s\n", uid.c_str(), path.c_str(),
                    core::LabelTable::sidecarPath(path).c_str());
        return 0;
    }
    if (dicom::SeriesOctree::isStructureSet(db, uid)) {  // contours, drawn onto an image's grid
        const auto grid = args.value("grid");
        if (!grid)
            throw core::Error("series " + uid + " is an RT Structure Set (contours): give the image octree whose "
                              "grid it is drawn onto, --grid IMAGE.hvo");
        core::JobContext job;
        std::vector<std::string> warnings;
        const auto path = dicom::SeriesOctree::buildStructureSet(db, uid, core::OctreeReader::open(*grid)->geometry(),
                                                                 job, &warnings, *out);
        for (const auto& w : warnings) std::fprintf(stderr, "holovox-cli: warning: %s\n", w.c_str());
        std::printf("structure set %s: label map %s on the grid of %s, ROIs' names and colours in %s\n", uid.c_str(),
                    path.c_str(), grid->c_str(), core::LabelTable::sidecarPath(path).c_str());
        return 0;
    }
    const auto scan = scanFiles(files);
    std::vector<std::string> notes;
    auto volumes = dicom::SeriesAssembler::assemble(scan.instances, notes);
    volumes.erase(std::remove_if(volumes.begin(), volumes.end(),
                                 [&](const dicom::SeriesVolume& v) { return v.seriesUid != uid; }),
                  volumes.end());
    if (volumes.empty()) throw core::Error("series " + uid + " has no image volume");
    std::size_t pick = 0;
    if (const char* name = args.value("volume") ? "volume" : args.value("stack") ? "stack" : nullptr) {
        pick = std::size_t(args.integer(name, 1, 1, long(volumes.size()))) - 1;
    } else {
        for (std::size_t i = 1; i < volumes.size(); ++i)
            if (volumes[i].slices.size() > volumes[pick].slices.size()) pick = i;
    }
    printVolume(volumes[pick], volumes.size() > 1 ? pick + 1 : 0);
    dicom::DicomSeriesSource source(volumes[pick]);
    OctreeBuildRunner::run(source, *out, core::BuildOptions{}, true);
    dicom::SeriesOctree::record(db, uid, *out);  // deleted, and said, when removed meanwhile
    return 0;
}

int exportDicomCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2,
                       {"o", "output", "syntax", "patient", "patient-id", "study", "series", "date", "accession",
                        "modality", "series-uid", "db", "volume"},
                       {"enhanced"});
    const auto out = args.value("o") ? args.value("o") : args.value("output");
    const auto fromSeries = args.value("series-uid");
    if (args.positional().size() != (fromSeries ? 0u : 1u) || !out)
        throw core::Error("usage: holovox-cli export-dicom INPUT -o FOLDER [--syntax S] [--enhanced] [--patient NAME] "
                          "[--modality CT|MR|PT|NM|OT] [--volume N]\n       holovox-cli export-dicom --series-uid UID [--db FILE] "
                          "[--volume N] -o FOLDER   (an imported series, keeping its patient, study and frame of reference)");
    dicom::DicomWriteOptions o;
    std::unique_ptr<core::VoxelSource> source;
    std::function<std::unique_ptr<core::VoxelSource>()> reopen;  // a float volume is read twice
    std::string input;
    if (fromSeries) {
        // A DICOM source keeps who and where it is: patient, study and frame of reference, so
        // the export files under the same study and registers with its source.
        dicom::StudyDatabase db(args.value("db").value_or(dicom::StudyDatabase::defaultPath()));
        core::JobContext job;
        const auto volume =
            dicom::SeriesOctree::assemble(db, *fromSeries, job, nullptr, int(args.integer("volume", 0, 0, 1 << 20)));
        const auto& first = volume.instances.front();
        o.patientName = first.patientName;
        o.patientId = first.patientId;
        o.patientBirthDate = first.patientBirthDate;
        o.patientSex = first.patientSex;
        o.studyUid = first.studyInstanceUid;
        o.studyDate = first.studyDate;
        o.studyDescription = first.studyDescription;
        o.accessionNumber = first.accessionNumber;
        o.frameOfReferenceUid = first.frameOfReferenceUid;
        o.seriesDescription = first.seriesDescription.empty() ? "Holovox export" : first.seriesDescription + " (Holovox)";
        input = *fromSeries;
        reopen = [volume] { return std::make_unique<dicom::DicomSeriesSource>(volume); };
    } else {
        input = args.positional()[0];
        if (std::filesystem::path(input).extension() == ".hvo")
            throw core::Error(input + ": export-dicom writes the source a volume was built from (a NIfTI, NRRD, ... "
                                      "file, or an imported series with --series-uid), not its octree");
        const auto volume = std::uint32_t(args.integer("volume", 1, 1, 1 << 20) - 1);  // 1-based, as build's
        reopen = [input, volume] { return core::VoxelSourceFactory::open(input, {}, volume); };
    }
    source = reopen();
    // What the source assumed or made up is said here and written into every image
    // (Derivation Description): an interpolated slice must not pass for an acquired one.
    std::string derivation = "Holovox export of " + (fromSeries ? "series " + input : std::filesystem::path(input).filename().string());
    for (const auto& w : source->warnings()) {
        std::fprintf(stderr, "holovox-cli: warning: %s\n", w.c_str());
        derivation += "; " + w;
    }
    o.derivation = derivation;
    if (auto v = args.value("modality")) {
        static const std::set<std::string> known = {"CT", "MR", "PT", "NM", "OT", "US", "XA", "CR", "DX", "RTDOSE", "SEG"};
        if (!known.count(*v)) throw core::Error("--modality " + *v + " is not a DICOM modality Holovox writes");
        o.modality = *v;
    }
    core::RescaledInt16Source* rescaled = nullptr;
    if (source->geometry().scalarType == core::ScalarType::Float32) {
        // DICOM images hold integers: a first pass finds the range, the second writes 16 bits
        // over it, and the largest error is reported. A CT's HU must stay within half a unit:
        // one far value (an outlier) would otherwise coarsen every other.
        const auto [lo, hi] = core::RescaledInt16Source::physicalRange(*source);
        const std::string modality = o.modality.empty() ? source->geometry().modality : o.modality;
        const double halfStep = (hi - lo) / 65535.0 / 2.0;
        if (modality == "CT" && !source->geometry().notHounsfield && halfStep > 0.5)
            throw core::Error(input + ": its float values run from " + std::to_string(lo) + " to " + std::to_string(hi) +
                              " HU; as 16-bit integers every value would move by up to " + std::to_string(halfStep) +
                              " HU (a CT holds about -1024 to 3071 HU: is a value wrong?)");
        auto r = std::make_unique<core::RescaledInt16Source>(reopen(), lo, hi);
        rescaled = r.get();
        source = std::move(r);
    }
    if (auto v = args.value("syntax")) o.transferSyntax = *v;
    if (auto v = args.value("patient")) o.patientName = *v;
    if (auto v = args.value("patient-id")) o.patientId = *v;
    if (auto v = args.value("study")) o.studyDescription = *v;
    if (auto v = args.value("series")) o.seriesDescription = *v;
    if (auto v = args.value("date")) o.studyDate = *v;
    if (auto v = args.value("accession")) o.accessionNumber = *v;
    o.enhancedMultiframe = args.flag("enhanced");
    if (!fromSeries && !args.value("patient") && !args.value("patient-id"))
        std::fprintf(stderr, "holovox-cli: warning: no --patient or --patient-id: the patient's name and ID are left "
                             "empty (unknown), not made up\n");
    ProgressBar bar("export");
    core::JobContext job(bar.observer());
    SignalCancel cancel(job);
    const auto files = dicom::DicomSeriesWriter::write(*source, *out, o, job);
    bar.finish();
    std::printf("wrote %zu DICOM files to %s\n", files.size(), out->c_str());
    if (rescaled)
        std::printf("float values written as 16-bit integers with slope %.9g and intercept %.9g: largest error %.3g\n",
                    source->geometry().rescaleSlope, source->geometry().rescaleIntercept, rescaled->largestError());
    return 0;
}

}  // namespace hvx::app
