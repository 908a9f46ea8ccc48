#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace hvx::core {

/// A continuous colour map for a volume laid over another (PET over CT, a parameter map over
/// anatomy): 256 RGB entries from the overlay window's low end (entry 0) to its high end.
///
/// Threading: a value type; const methods are safe from any thread.
class ColorMap {
public:
    using Rgb = std::array<std::uint8_t, 3>;
    /// The built-in maps, in menu order: grey, hot, rainbow, pet, cool.
    static const std::vector<std::string>& builtinNames();
    /// A built-in map by name (case-insensitive); throws core::Error listing the names otherwise.
    static ColorMap named(const std::string& name);
    /// A map from a file: mricron's binary .lut (768 bytes: 256 reds, 256 greens, 256 blues) or
    /// a text colour table (3D Slicer's .ctbl / .txt, FreeSurfer's LUT: "index name R G B A"
    /// lines, their entries spread from the smallest index to the largest). Throws core::Error
    /// naming the file and the line for anything else.
    static ColorMap load(const std::string& path);
    /// A built-in name, or else a file path.
    static ColorMap namedOrFile(const std::string& nameOrPath);

    const std::string& name() const { return name_; }
    /// The colour at t in [0, 1] (clamped): entry round(t·255).
    Rgb at(double t) const;
    const std::array<Rgb, 256>& entries() const { return entries_; }

private:
    std::string name_;
    std::array<Rgb, 256> entries_{};
};

}  // namespace hvx::core
