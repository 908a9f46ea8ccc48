#include "render/ComputeProgram.h"

#include <epoxy/gl.h>

#include <vector>

#include "core/base/Error.h"

namespace hvx::render {

ComputeProgram::ComputeProgram(const ShaderLibrary& library, const std::string& name,
                               const std::vector<std::string>& defines) {
    const auto source = library.expand(name, defines);
    const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
    std::vector<const char*> strings;
    for (const auto& s : source.strings) strings.push_back(s.c_str());
    glShaderSource(shader, GLsizei(strings.size()), strings.data(), nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
        std::string log(std::size_t(std::max(length, 1)), '\0');
        glGetShaderInfoLog(shader, length, nullptr, log.data());
        glDeleteShader(shader);
        throw core::Error("shader " + name + " does not compile:\n" + ShaderLibrary::mapLog(log.c_str(), source));
    }
    program_ = glCreateProgram();
    glAttachShader(program_, shader);
    glLinkProgram(program_);
    glDeleteShader(shader);
    glGetProgramiv(program_, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetProgramiv(program_, GL_INFO_LOG_LENGTH, &length);
        std::string log(std::size_t(std::max(length, 1)), '\0');
        glGetProgramInfoLog(program_, length, nullptr, log.data());
        glDeleteProgram(program_);
        program_ = 0;
        throw core::Error("shader " + name + " does not link:\n" + ShaderLibrary::mapLog(log.c_str(), source));
    }
}

ComputeProgram::~ComputeProgram() {
    if (program_) glDeleteProgram(program_);
}

void ComputeProgram::use() const { glUseProgram(program_); }

int ComputeProgram::uniform(const char* n) const { return glGetUniformLocation(program_, n); }

}  // namespace hvx::render
