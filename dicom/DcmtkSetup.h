#pragma once

namespace hvx::dicom {

/// One-time process setup of DCMTK: decoders for JPEG, JPEG-LS and RLE registered, and DCMTK's
/// own logging switched off (Holovox reports problems itself, one sentence per file), and a
/// socket read that gets nothing for kSocketReadTimeoutSeconds is an error.
/// Private to dicom/: call ensure() before touching DCMTK.
class DcmtkSetup {
public:
    static void ensure();
    static constexpr int kSocketReadTimeoutSeconds = 10;
};

}  // namespace hvx::dicom
