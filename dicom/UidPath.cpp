#include "dicom/UidPath.h"

#include <cctype>
#include <cstdint>
#include <cstdio>

namespace hvx::dicom {

namespace {
/// FNV-1a, 64 bits: a short, stable fingerprint of the original text.
std::uint64_t fingerprint(const std::string& s) {
    std::uint64_t h = 1469598103934665603ull;
    for (unsigned char c : s) {
        h ^= c;
        h *= 1099511628211ull;
    }
    return h;
}
}  // namespace

std::string UidPath::component(const std::string& uid) {
    std::string out;
    bool changed = false;
    for (char c : uid) {
        const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-';
        out += ok ? c : '_';
        changed = changed || !ok;
    }
    if (out.empty() || out.find_first_not_of('.') == std::string::npos) {
        out = "_" + out;
        changed = true;
    }
    if (!changed && out.size() <= 64) return out;
    // Sanitised or shortened: two UIDs could now read the same, so the original's fingerprint
    // goes with it ("1.2_3" from "1.2/3" and from "1.2\3" stay apart).
    char tag[24];
    std::snprintf(tag, sizeof tag, "-h%012llx", static_cast<unsigned long long>(fingerprint(uid) & 0xffffffffffffull));
    if (out.size() > 48) out.resize(48);
    return out + tag;
}

}  // namespace hvx::dicom
