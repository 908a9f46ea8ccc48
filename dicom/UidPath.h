#pragma once
#include <string>

namespace hvx::dicom {

/// Turns a UID (or any identifier received from outside) into one safe path component:
/// only [0-9A-Za-z.-] survive, anything else becomes '_', at most 64 characters, never empty,
/// never "." or "..", so a hostile UID cannot escape or collide with a folder.
class UidPath {
public:
    static std::string component(const std::string& uid);
};

}  // namespace hvx::dicom
