#pragma once
#include <string>
#include <vector>

#include "dicom/PacsQuery.h"

namespace hvx::dicom {

/// Outcome of a STOW-RS upload, from the server's answer (PS3.18 §10.5.3).
struct StowOutcome {
    std::vector<std::string> stored;  ///< Referenced SOP Sequence: SOP Instance UIDs accepted
    std::vector<std::string> failed;  ///< Failed SOP Sequence: "UID (reason 0xCODE)"
};

/// Reading the DICOM JSON model (PS3.18 Annex F) that QIDO-RS and STOW-RS answer with. Anything
/// that is not that model (not JSON, not an array of objects, values of the wrong kind) throws
/// core::Error with a sentence prefixed by `what`.
class DicomJson {
public:
    /// A QIDO-RS answer as query results at `level` (an empty body is no result).
    static std::vector<QueryResult> queryResults(const std::string& body, QueryLevel level, const std::string& what);
    /// A STOW-RS answer (an empty body is an empty outcome).
    static StowOutcome stowOutcome(const std::string& body, const std::string& what);
};

}  // namespace hvx::dicom
