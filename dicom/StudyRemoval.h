#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace hvx::dicom {

class StudyDatabase;

/// Removes a study from this workstation: its rows in the study database, and the files that
/// are Holovox's own: the instances received into its storage folder (by a retrieve or the
/// listener; the archive keeps the originals) and the octrees built for the study's series.
/// Files imported from the user's own folders are never deleted, only forgotten. What a study
/// whose patient the archive has corrected since needs before it can be retrieved again (the
/// database refuses a study UID under another patient).
class StudyRemoval {
public:
    struct Result {
        std::string patient;               ///< "NAME (ID)" of the study removed
        std::size_t forgotten = 0;         ///< instances taken out of the index
        std::size_t deleted = 0;           ///< of them, received files deleted from the storage folder
        std::size_t kept = 0;              ///< of them, files outside it, left where they are
        std::size_t shared = 0;            ///< of them, received files another database still indexes, left too
        std::vector<std::string> sharers;  ///< those databases (StorageOwners), or why one could not be read
        std::size_t octrees = 0;           ///< octree files deleted
        std::vector<std::string> failed;   ///< "PATH: why" for files that could not be deleted
        /// Of the received files that could not be deleted, those indexed again: the study stays
        /// listed with them, rather than leaving them in the storage folder unknown to the index.
        std::size_t reindexed = 0;
    };
    /// Removes `studyUid` (throws core::Error naming an unknown study, changing nothing). A file
    /// is deleted only where IncomingStore would have received it: `storageDir`/<study>/<series>/
    /// <sop>.dcm, a plain file, not a link (the series and study folders left empty go too); an
    /// octree only directly in `octreeDir` and named for one of the study's series, unless the
    /// database records it for another. A received file that another study database sharing
    /// the storage folder indexes (StorageOwners) stays; so do all of them when one of those
    /// databases cannot be read. A received file that cannot be deleted (a read-only folder, a
    /// file marked immutable) is indexed again (Result::reindexed), so that removing the study
    /// again once it can be deleted finishes the job.
    static Result remove(StudyDatabase& db, const std::string& studyUid, const std::string& storageDir,
                         const std::string& octreeDir);
};

}  // namespace hvx::dicom
