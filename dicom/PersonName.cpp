#include "dicom/PersonName.h"

namespace hvx::dicom {

namespace {
bool validUtf8(const std::string& s) {
    for (std::size_t i = 0; i < s.size();) {
        const auto c = static_cast<unsigned char>(s[i]);
        const std::size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
        if (n == 0 || i + n > s.size()) return false;
        for (std::size_t k = 1; k < n; ++k)
            if ((static_cast<unsigned char>(s[i + k]) >> 6) != 0x2) return false;
        i += n;
    }
    return true;
}
}  // namespace

std::string personNameKey(const std::string& name) {
    std::string s;
    if (validUtf8(name)) {
        s = name;
    } else {  // Latin-1: each byte is the code point
        for (const char ch : name) {
            const auto c = static_cast<unsigned char>(ch);
            if (c < 0x80) {
                s += ch;
            } else {
                s += char(0xC0 | (c >> 6));
                s += char(0x80 | (c & 0x3F));
            }
        }
    }
    for (auto& c : s)  // ASCII only: a locale's toupper would change UTF-8 bytes
        if (c >= 'a' && c <= 'z') c = char(c - 'a' + 'A');
    while (!s.empty() && (s.back() == '^' || s.back() == ' ' || s.back() == '=')) s.pop_back();
    return s;
}

}  // namespace hvx::dicom
