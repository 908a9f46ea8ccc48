#pragma once
#include <memory>

class DcmTransportLayer;  // private to dicom/: only .cpp files of this module use this

namespace hvx::dicom {

/// DCMTK's transport layer for plain TCP, with each read followed by TCP_QUICKACK: the peer's
/// next segment is acknowledged at once instead of after Linux's delayed-ACK timer (~40 ms).
/// TCP_NODELAY on our side is not enough against a peer that leaves Nagle's algorithm on (an
/// unmodified Orthanc or dcmqrscp on Debian 12): its next small DIMSE message waits for our ACK
/// of the previous one. Linux does not keep quick-ack mode, so it is asked for after every read.
/// Used for every association without TLS, as requestor (PacsClient) and acceptor
/// (StorageServer). The layer must outlive the network that uses it.
std::unique_ptr<DcmTransportLayer> makeQuickAckTransport();

}  // namespace hvx::dicom
