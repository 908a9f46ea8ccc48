#pragma once
#include <string>
#include <vector>

namespace hvx::dicom {

/// The study databases that index instances received into a storage folder, listed in
/// `<storage>/.holovox-databases` (one absolute path a line). Two databases may share one
/// storage folder (the PACS settings name one folder; `--db` picks another database); removing a
/// study from one must not delete a file the other still indexes (StudyRemoval).
class StorageOwners {
public:
    /// Adds `dbPath` (made absolute) to the folder's list when it is not there yet. A folder that
    /// cannot be written is left as it is: the receive itself says what is wrong with it.
    static void add(const std::string& storageDir, const std::string& dbPath);
    /// The databases the folder's list names, other than `dbPath`, whose files exist.
    static std::vector<std::string> othersThan(const std::string& storageDir, const std::string& dbPath);
    /// The list's file name in a storage folder.
    static constexpr const char* kListName = ".holovox-databases";
};

}  // namespace hvx::dicom
