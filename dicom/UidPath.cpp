#include "dicom/UidPath.h"

#include <cctype>

namespace hvx::dicom {

std::string UidPath::component(const std::string& uid) {
    std::string out;
    for (char c : uid) {
        if (out.size() >= 64) break;
        const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-';
        out += ok ? c : '_';
    }
    if (out.empty() || out.find_first_not_of('.') == std::string::npos) out = "_" + out;
    return out;
}

}  // namespace hvx::dicom
