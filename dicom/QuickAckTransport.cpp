#include "dicom/QuickAckTransport.h"

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmnet/dcmlayer.h>
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

class QuickAckLayer : public DcmTransportLayer {
public:
    DcmTransportConnection* createConnection(DcmNativeSocketType openSocket, OFBool) override {
        return new QuickAckConnection(openSocket);
    }
};
}  // namespace

std::unique_ptr<DcmTransportLayer> makeQuickAckTransport() { return std::make_unique<QuickAckLayer>(); }

}  // namespace hvx::dicom
