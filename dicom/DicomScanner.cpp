#include "dicom/DicomScanner.h"

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcdicdir.h>
#include <dcmtk/dcmdata/dcdirrec.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <mutex>
#include <set>

#include "core/base/Error.h"
#include "core/base/ThreadPool.h"
#include "dicom/DcmtkSetup.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/IncomingStore.h"
#include "dicom/StorageOwners.h"

namespace fs = std::filesystem;

namespace hvx::dicom {

namespace {
void collectReferences(DcmDirectoryRecord* rec, const fs::path& base, std::vector<std::string>& out, int depth) {
    if (!rec || depth > 16) return;
    OFString ref;
    if (rec->findAndGetOFStringArray(DCM_ReferencedFileID, ref).good() && !ref.empty()) {
        std::string rel = ref.c_str();
        std::replace(rel.begin(), rel.end(), '\\', '/');
        // A reference must stay inside the medium.
        if (rel.find("..") == std::string::npos && rel.front() != '/') out.push_back((base / rel).string());
    }
    for (unsigned long i = 0; i < rec->cardSub(); ++i) collectReferences(rec->getSub(i), base, out, depth + 1);
}

bool isDicomdirName(const fs::path& p) {
    std::string n = p.filename().string();
    std::transform(n.begin(), n.end(), n.begin(), ::toupper);
    return n == "DICOMDIR";
}

// Finds a case-insensitive existing file for a DICOMDIR reference (CDs are often upper case).
std::string resolveCase(const std::string& path) {
    std::error_code ec;
    if (fs::exists(path, ec)) return path;
    fs::path cur = fs::path(path).root_path();
    fs::path rel = fs::path(path).relative_path();
    for (const auto& part : rel) {
        fs::path next = cur / part;
        if (!fs::exists(next, ec)) {
            std::string want = part.string();
            std::transform(want.begin(), want.end(), want.begin(), ::toupper);
            bool found = false;
            for (const auto& e : fs::directory_iterator(cur, ec)) {
                std::string n = e.path().filename().string();
                std::transform(n.begin(), n.end(), n.begin(), ::toupper);
                if (n == want) {
                    next = e.path();
                    found = true;
                    break;
                }
            }
            if (!found) return path;
        }
        cur = next;
    }
    return cur.string();
}
/// Whether `p` is a received-instance storage folder's own bookkeeping (IncomingStore,
/// StorageOwners) in a folder that is one: the list of databases, the instances still being
/// received (.incoming) and those refused on receipt and set aside (.conflicts). Importing a
/// storage folder had counted the list as a file that is not DICOM and read half-received files.
bool isStorageBookkeeping(const fs::path& p) {
    const std::string name = p.filename().string();
    if (name != StorageOwners::kListName && name != IncomingStore::kIncomingFolder &&
        name != IncomingStore::kConflictsFolder)
        return false;
    std::error_code ec;
    const fs::path folder = p.parent_path();
    return fs::is_regular_file(folder / StorageOwners::kListName, ec) ||
           fs::is_directory(folder / IncomingStore::kIncomingFolder, ec);
}

std::size_t countFiles(const fs::path& folder) {
    std::size_t n = 0;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(folder, fs::directory_options::skip_permission_denied, ec);
         it != fs::recursive_directory_iterator(); it.increment(ec)) {
        if (ec) break;
        if (it->is_regular_file(ec)) ++n;
    }
    return n;
}
}  // namespace

std::vector<std::string> DicomScanner::filesOfDicomdir(const std::string& dicomdirPath) {
    DcmtkSetup::ensure();
    DcmDicomDir dir(dicomdirPath.c_str());
    if (dir.error().bad()) throw core::Error(dicomdirPath + ": unreadable DICOMDIR (" + dir.error().text() + ")");
    std::vector<std::string> files;
    collectReferences(&dir.getRootRecord(), fs::path(dicomdirPath).parent_path(), files, 0);
    for (auto& f : files) f = resolveCase(f);
    return files;
}

DicomScanner::Result DicomScanner::scan(const std::vector<std::string>& paths, core::JobContext& job) {
    job.report(0.0, "finding files");
    Result r;
    std::vector<std::string> files;
    std::error_code ec;
    for (const auto& p : paths) {
        if (!fs::exists(p, ec)) throw core::Error(p + ": no such file or folder");
        if (fs::is_directory(p, ec)) {
            const fs::path dd = fs::path(p) / "DICOMDIR";
            std::vector<std::string> referenced;
            if (fs::exists(dd, ec)) {
                try {
                    referenced = filesOfDicomdir(dd.string());
                } catch (const core::Error&) {
                    referenced.clear();  // fall back to walking the folder
                }
            }
            // What the DICOMDIR lists (a referenced file that is missing counts as broken), and
            // the folder's other files: a series copied in beside a DICOMDIR, or a referenced
            // file's copy elsewhere, had been ignored without a word.
            files.insert(files.end(), referenced.begin(), referenced.end());
            for (auto it = fs::recursive_directory_iterator(p, fs::directory_options::skip_permission_denied, ec);
                 it != fs::recursive_directory_iterator(); it.increment(ec)) {
                if (ec) break;
                if (isStorageBookkeeping(it->path())) {  // not an instance to import: counted, not read
                    if (it->is_directory(ec)) {
                        r.setAside += countFiles(it->path());
                        it.disable_recursion_pending();
                    }
                    continue;
                }
                if (it->is_regular_file(ec) && !isDicomdirName(it->path())) files.push_back(it->path().string());
            }
        } else if (isDicomdirName(p)) {
            const auto referenced = filesOfDicomdir(p);
            files.insert(files.end(), referenced.begin(), referenced.end());
        } else {
            files.push_back(p);
        }
    }
    // One spelling per file: a DICOMDIR's references and the walk of "dd//" had differed.
    for (auto& f : files) f = fs::path(f).lexically_normal().string();
    std::sort(files.begin(), files.end());
    files.erase(std::unique(files.begin(), files.end()), files.end());

    r.filesSeen = files.size();
    std::vector<DicomInstance> found(files.size());
    std::vector<signed char> state(files.size(), 0);  // 1 dicom, 2 not dicom, 3 broken
    std::vector<std::string> reasons(files.size());
    std::atomic<std::size_t> done{0};
    core::ThreadPool::shared().parallelFor(files.size(), [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
            job.throwIfCancelled();
            try {
                state[i] = DicomHeaderReader::read(files[i], found[i]) == DicomHeaderReader::Kind::Dicom ? 1 : 2;
            } catch (const std::exception& err) {
                state[i] = 3;
                reasons[i] = err.what();
            }
            job.report(double(++done) / double(files.size()), "reading headers");
        }
    }, 8);
    for (std::size_t i = 0; i < files.size(); ++i) {
        if (state[i] == 1) r.instances.push_back(std::move(found[i]));
        else if (state[i] == 2) ++r.notDicom;
        else {
            ++r.broken;
            if (r.brokenReasons.size() < 5) r.brokenReasons.push_back(reasons[i]);
        }
    }
    job.report(1.0, "done");
    return r;
}

}  // namespace hvx::dicom
