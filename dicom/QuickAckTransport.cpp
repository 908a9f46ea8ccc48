#include "dicom/QuickAckTransport.h"

#include <dcmtk/dcmnet/dcmtrans.h>

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

namespace hvx::dicom {

namespace {
class QuickAckConnection : public DcmTCPConnection {
public:
    explicit QuickAckConnection(DcmNativeSocketType socket) : DcmTCPConnection(socket) {
        const int one = 1;
        ::setsockopt(int(getSocket()), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        acknowledge();
    }
    ssize_t read(void* buffer, size_t bytes) override {
        const ssize_t n = DcmTCPConnection::read(buffer, bytes);
        acknowledge();
        return n;
    }

private:
    void acknowledge() {
        const int one = 1;
        ::setsockopt(int(getSocket()), IPPROTO_TCP, TCP_QUICKACK, &one, sizeof one);
    }
};
}  // namespace

DcmTransportConnection* QuickAckTransport::createConnection(DcmNativeSocketType openSocket, OFBool) {
    return new QuickAckConnection(openSocket);
}

}  // namespace hvx::dicom
