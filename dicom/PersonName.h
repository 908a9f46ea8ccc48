#pragma once
#include <string>

namespace hvx::dicom {

/// A Person Name as a key under which the ways systems write one name agree: case (ASCII),
/// spaces and empty trailing components ("DOE^JANE^^" and "Doe^Jane" are one), and Latin-1
/// bytes of a file that declared no character set read as the UTF-8 they stand for (a name
/// stored before character sets were converted matches the same name converted).
std::string personNameKey(const std::string& name);

}  // namespace hvx::dicom
