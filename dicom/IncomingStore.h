#pragma once
#include <cstdint>
#include <string>

#include "dicom/DicomInstance.h"

namespace hvx::dicom {

/// Where received instances land: `storageDir/<study>/<series>/<sop>.dcm`, each UID made a
/// safe path component (UidPath). A receiver writes the incoming stream to temporaryPath()
/// (under storageDir/.incoming; the name is unique in the process and created exclusively),
/// then finalize() reads its header, flushes it and renames it into place without replacing
/// anything, then flushes the folder: no half-written file ever appears in the tree and no UID
/// can escape the folder. The same instance arriving again with the same dataset bytes (the File
/// Meta Information, which names the sender, may differ) changes nothing; with other bytes it
/// is set aside under storageDir/.conflicts and reported, and the stored one is kept.
///
/// Threading: temporaryPath() and finalize() may be called from several threads.
class IncomingStore {
public:
    /// Creates the folders; throws core::Error naming the folder when it cannot. No instance is
    /// taken while the folder's file system has less than `minFreeBytes` free.
    explicit IncomingStore(std::string storageDir, std::uint64_t minFreeBytes = 0);
    /// A fresh temporary file name inside the storage folder. Throws core::Error when it cannot
    /// be made, or when the free space is below the floor (saying how much is free).
    std::string temporaryPath();
    /// As temporaryPath(), with the file left open for writing: `fd` is the caller's to close.
    /// (Opening the empty file again with truncation would make ext4 write it back at close.)
    std::string temporaryFile(int& fd);
    /// Bytes free for an unprivileged writer on the storage folder's file system.
    std::uint64_t freeBytes() const;
    /// Moves a completely received temporary file into place and returns its header (path set
    /// to the final file). Throws core::Error (and removes the file) when it is not valid DICOM.
    /// place() then flushFolder(): the name is on disk when it returns.
    DicomInstance finalize(const std::string& temporary);
    /// An instance moved into place, its bytes on disk; its name is on disk once `folder` has
    /// been flushed.
    struct Placed {
        DicomInstance instance;
        std::string folder;
    };
    /// As finalize() without the folder's flush, so that one flush can cover many renames
    /// (IncomingFiler); the instance must not be reported before flushFolder(placed.folder).
    Placed place(const std::string& temporary);
    /// Where an instance of these UIDs is placed under `storageDir`:
    /// <storageDir>/<study>/<series>/<sop>.dcm, each a UidPath component.
    static std::string placeOf(const std::string& storageDir, const std::string& studyUid, const std::string& seriesUid,
                               const std::string& sopUid);
    /// Flushes a folder's entries to disk (fsync of the folder).
    static void flushFolder(const std::string& folder);
    const std::string& storageDir() const { return dir_; }
    /// The store's own folders inside the storage folder: instances being received, and
    /// objects refused on receipt and set aside.
    static constexpr const char* kIncomingFolder = ".incoming";
    static constexpr const char* kConflictsFolder = ".conflicts";

private:
    std::string dir_;
    std::uint64_t minFreeBytes_ = 0;
};

}  // namespace hvx::dicom
