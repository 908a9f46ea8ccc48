#include "tests/support/TestCertificates.h"

#include <fstream>
#include <stdexcept>

#include "tests/support/ProcessRunner.h"

namespace hvx::test {

void makeTestCertificates(const std::string& dir, const std::string& serverNames) {
    std::ofstream(dir + "/names.cnf") << "subjectAltName=" << serverNames << "\n";
    const auto r = runCommand(
        "cd " + dir + " && openssl req -x509 -newkey rsa:2048 -nodes -keyout ca.key -out ca.crt -days 2 "
        "-subj /CN=HolovoxTestCA && openssl req -newkey rsa:2048 -nodes -keyout server.key -out server.csr "
        "-subj /CN=HolovoxTestPacs && openssl x509 -req -in server.csr -CA ca.crt -CAkey ca.key -CAcreateserial "
        "-extfile names.cnf -out server.crt -days 2 && openssl req -newkey rsa:2048 -nodes -keyout client.key "
        "-out client.csr -subj /CN=HolovoxTestModality && openssl x509 -req -in client.csr -CA ca.crt -CAkey ca.key "
        "-CAcreateserial -out client.crt -days 2 2>&1");
    if (r.exitCode != 0) throw std::runtime_error("openssl failed: " + r.output);
}

}  // namespace hvx::test
