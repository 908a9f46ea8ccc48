#pragma once

namespace hvx::dicom {

/// One-time process setup of DCMTK: decoders for JPEG, JPEG-LS and RLE registered, and DCMTK's
/// own logging switched off (Holovox reports problems itself, one sentence per file).
/// Private to dicom/: call ensure() before touching DCMTK.
class DcmtkSetup {
public:
    static void ensure();
};

}  // namespace hvx::dicom
