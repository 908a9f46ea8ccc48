#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "dicom/PacsClient.h"

class DcmDataset;  // private to dicom/: only .cpp files of this module use these helpers

namespace hvx::dicom {

/// The DICOM details shared by Holovox's client and storage server: which SOP classes and
/// transfer syntaxes are negotiated, how query and retrieve identifiers are built, and how
/// network failures and DIMSE statuses become plain sentences that say what to check.
class PacsProtocol {
public:
    /// Explicit and implicit little endian, for C-ECHO, C-FIND, C-MOVE.
    static std::vector<std::string> basicSyntaxes();
    /// What we accept for received images: uncompressed, deflate, RLE, JPEG, JPEG-LS, JPEG 2000.
    static std::vector<std::string> storageSyntaxes();
    /// Image storage SOP classes negotiated for C-GET (CT, MR, enhanced CT/MR, secondary
    /// capture and the other common cross-sectional and projection images).
    static std::vector<const char*> storageClasses();
    static void fillQuery(DcmDataset& query, QueryLevel level, const QueryKeys& keys);
    /// Retrieve keys for a study, a series, or (with `sopUids`) some instances of a series.
    static void fillRetrieve(DcmDataset& keys, const std::string& studyUid, const std::string& seriesUid,
                             const std::vector<std::string>& sopUids = {});
    static std::string describeAssociationFailure(const std::string& where, const std::string& reason,
                                                  const std::string& localAe, const std::string& remoteAe,
                                                  int timeoutSeconds);
    static std::string describeDimseFailure(const std::string& where, const std::string& operation,
                                            const std::string& reason, int timeoutSeconds);
    /// Throws core::Error for a failed, refused or partly failed final status.
    static void checkFinalStatus(const std::string& where, const std::string& operation, std::uint16_t status,
                                 const std::string& destinationAe);
};

}  // namespace hvx::dicom
