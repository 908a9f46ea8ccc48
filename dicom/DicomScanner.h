#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "core/base/JobContext.h"
#include "dicom/DicomInstance.h"

namespace hvx::dicom {

/// Finds DICOM files under folders, DICOMDIR files and single files, and reads their headers
/// (never the pixel data) on all cores.
///
/// Threading: scan() blocks the calling (job) thread and uses ThreadPool::shared().
class DicomScanner {
public:
    struct Result {
        std::vector<DicomInstance> instances;  ///< every readable DICOM file, images or not
        std::size_t filesSeen = 0;
        std::size_t notDicom = 0;  ///< skipped quietly
        std::size_t broken = 0;    ///< DICOM files that could not be read
        std::vector<std::string> brokenReasons;  ///< the first few, one sentence each
        /// Files of a storage folder's .incoming (still being received) and .conflicts (refused on
        /// receipt), not read; its list of databases is not counted at all.
        std::size_t setAside = 0;
    };
    /// Scans each path: a DICOMDIR file (its referenced files), a folder (the files its DICOMDIR
    /// references, if it has one that parses, and every file below it), or a single file. Throws core::Error only when
    /// a given path does not exist; core::Cancelled when the job is cancelled. In a
    /// received-instance storage folder, Holovox's own files are left out (Result::setAside).
    static Result scan(const std::vector<std::string>& paths, core::JobContext& job);
    /// The files a DICOMDIR references (paths resolved against its folder); throws core::Error.
    static std::vector<std::string> filesOfDicomdir(const std::string& dicomdirPath);
};

}  // namespace hvx::dicom
