#include "dicom/DcmtkSetup.h"

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcrledrg.h>
#include <dcmtk/dcmdata/dcvr.h>
#include <dcmtk/dcmjpeg/djdecode.h>
#include <dcmtk/dcmjpls/djdecode.h>
#include <dcmtk/dcmnet/dcmtrans.h>
#include <dcmtk/oflog/oflog.h>

#include <cstdlib>
#include <mutex>

namespace hvx::dicom {

void DcmtkSetup::ensure() {
    static std::once_flag once;
    std::call_once(once, [] {
        OFLog::configure(OFLogger::OFF_LOG_LEVEL);
        DJDecoderRegistration::registerCodecs();
        DJLSDecoderRegistration::registerCodecs();
        DcmRLEDecoderRegistration::registerCodecs();
        // A read that gets no byte for this long fails, instead of DCMTK's 60 s. Waiting for the
        // next DIMSE message is a select() bounded by each node's own timeout; this bounds a
        // peer that stops in the middle of a PDU, and the storage receiver's read of an
        // A-ASSOCIATE-RQ (on that connection's own worker).
        dcmSocketReceiveTimeout.set(kSocketReadTimeoutSeconds);
        // An element stored with VR UN whose tag the dictionary knows is read with the
        // dictionary's VR (PS3.5 6.2.2): a file that passed through a system that did not know
        // them (pydicom's rtdose_rle_1frame.dcm) keeps its Modality, names and DoseGridScaling,
        // instead of a dose a million times too high.
        dcmEnableUnknownVRConversion.set(OFTrue);
        // DCMTK 3.6.7 leaves Nagle's algorithm on unless TCP_NODELAY=1 is in the environment,
        // which it reads on every connection it opens or accepts: each small DIMSE message
        // then waits out the peer's delayed ACK (about 40 ms an instance). A value the user
        // set is kept.
        ::setenv("TCP_NODELAY", "1", 0);
    });
}

}  // namespace hvx::dicom
