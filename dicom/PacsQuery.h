#pragma once
#include <string>

namespace hvx::dicom {

/// Query/retrieve level of a Study Root C-FIND.
enum class QueryLevel { Study, Series, Image };

/// Matching keys of a query. Empty keys match everything. patientName takes DICOM wildcards
/// (* and ?); studyDate is YYYYMMDD or a range "YYYYMMDD-YYYYMMDD" (either end may be open).
struct QueryKeys {
    std::string patientName, patientId, studyDate, modality, accessionNumber, studyDescription;
    std::string studyUid, seriesUid;  ///< restrict SERIES and IMAGE queries
};

/// One C-FIND answer.
struct QueryResult {
    QueryLevel level = QueryLevel::Study;
    std::string patientName, patientId, patientBirthDate;
    std::string studyUid, studyDate, studyTime, studyDescription, accessionNumber, modalitiesInStudy;
    std::string seriesUid, seriesDescription, modality;
    int seriesNumber = 0, instanceNumber = 0, numberOfInstances = 0;
    std::string sopInstanceUid;
};

/// Sub-operation counts of a running C-GET or C-MOVE, from the PACS's pending responses.
struct RetrieveProgress {
    int remaining = 0, completed = 0, failed = 0, warning = 0;
    int received = 0;  ///< instances this client stored itself (C-GET)
};

}  // namespace hvx::dicom
