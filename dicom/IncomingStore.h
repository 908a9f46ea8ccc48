#pragma once
#include <atomic>
#include <string>

#include "dicom/DicomInstance.h"

namespace hvx::dicom {

/// Where received instances land: `storageDir/<study>/<series>/<sop>.dcm`, each UID made a
/// safe path component (UidPath). A receiver writes the incoming stream to temporaryPath()
/// (under storageDir/.incoming), then finalize() reads its header and renames it into place,
/// so no half-written file ever appears in the tree and no UID can escape the folder.
///
/// Threading: temporaryPath() and finalize() may be called from several threads.
class IncomingStore {
public:
    /// Creates the folders; throws core::Error naming the folder when it cannot.
    explicit IncomingStore(std::string storageDir);
    /// A fresh temporary file name inside the storage folder.
    std::string temporaryPath();
    /// Moves a completely received temporary file into place and returns its header (path set
    /// to the final file). Throws core::Error (and removes the file) when it is not valid DICOM.
    DicomInstance finalize(const std::string& temporary);
    const std::string& storageDir() const { return dir_; }

private:
    std::string dir_;
    std::atomic<unsigned long> counter_{0};
};

}  // namespace hvx::dicom
