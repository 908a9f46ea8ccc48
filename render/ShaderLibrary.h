#pragma once
#include <map>
#include <string>
#include <vector>

namespace hvx::render {

/// GLSL sources by file name, with `#include "name"` expanded at load time (each file once)
/// and `#line` markers so a compiler message can be mapped back to file:line. The embedded
/// library holds resources/shaders/*.glsl and core/*/*.glsl, built into the binary.
///
/// Threading: immutable; share freely.
class ShaderLibrary {
public:
    explicit ShaderLibrary(std::map<std::string, std::string> files);
    /// The shaders embedded at build time.
    static const ShaderLibrary& embedded();

    /// Lines of file k are numbered k * kLineBlock + line in the expanded source.
    static constexpr int kLineBlock = 100000;
    /// The expanded program as source strings (one per uninterrupted run of a file).
    struct Source {
        std::vector<std::string> strings;
        std::vector<std::string> files;  ///< file index -> file name (0: #version and defines)
        std::string text() const;
    };
    /// Expands `name` and its includes; `defines` ("NAME VALUE" or "NAME") go right after
    /// #version. Throws core::Error for a missing file or an include cycle deeper than 16.
    Source expand(const std::string& name, const std::vector<std::string>& defines = {}) const;
    /// Rewrites driver locations such as "0:12(5):" (Mesa) or "0(12) :" (NVIDIA) into
    /// "file.glsl:12:".
    static std::string mapLog(const std::string& log, const Source& source);
    bool has(const std::string& name) const { return files_.count(name) != 0; }

private:
    void append(const std::string& name, Source& out, std::vector<std::string>& done, int depth) const;
    std::map<std::string, std::string> files_;
};

}  // namespace hvx::render
