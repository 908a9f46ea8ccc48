#pragma once
#include <cctype>
#include <string>

namespace hvx::core {

/// `s` without the spaces, tabs and carriage returns at either end (header lines of text formats).
inline std::string trimBlanks(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r");
    const auto e = s.find_last_not_of(" \t\r");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

/// `s` in lower case (ASCII): keywords and names that text formats read in any case.
inline std::string lowercase(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

}  // namespace hvx::core
