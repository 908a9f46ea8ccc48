#pragma once
#include <string>

namespace hvx::test {

/// Makes, with openssl, in `dir`: a CA (ca.crt, ca.key), a server certificate it signs for the
/// subjectAltName entries `serverNames` (server.crt, server.key) and a client certificate it
/// signs (client.crt, client.key). Throws std::runtime_error with openssl's words on failure.
void makeTestCertificates(const std::string& dir, const std::string& serverNames = "IP:127.0.0.1,DNS:localhost");

}  // namespace hvx::test
