#pragma once
#include <string>

namespace hvx::dicom {

/// Turns a UID (or any identifier received from outside) into one safe path component:
/// only [0-9A-Za-z.-] survive, anything else becomes '_', never empty, never "." or "..", so a
/// hostile UID cannot escape the folder. A valid UID (at most 64 such characters) is kept as it
/// is; one that had to be changed or shortened gets a fingerprint of the original ("-h" and 12
/// hex digits, at most 62 characters in all), so two UIDs never share a component.
class UidPath {
public:
    static std::string component(const std::string& uid);
};

}  // namespace hvx::dicom
