#pragma once
#include <string>
#include <vector>

#include "render/ShaderLibrary.h"

namespace hvx::render {

/// A linked OpenGL compute program built from the shader library with a set of #defines
/// (a static variant). Compile errors become a core::Error whose text names file:line.
///
/// Threading: GL thread only (a current 4.5 context is required).
class ComputeProgram {
public:
    ComputeProgram(const ShaderLibrary& library, const std::string& name, const std::vector<std::string>& defines = {});
    ~ComputeProgram();
    ComputeProgram(const ComputeProgram&) = delete;
    ComputeProgram& operator=(const ComputeProgram&) = delete;
    unsigned id() const { return program_; }
    void use() const;
    /// Location of a uniform (-1 when the driver optimised it away).
    int uniform(const char* name) const;

private:
    unsigned program_ = 0;
};

}  // namespace hvx::render
