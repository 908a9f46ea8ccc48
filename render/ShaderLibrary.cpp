#include "render/ShaderLibrary.h"

#include <algorithm>
#include <regex>
#include <sstream>

#include "core/base/Error.h"

namespace hvx::render {

const std::map<std::string, std::string>& embeddedShaderFiles();  // generated at build time

ShaderLibrary::ShaderLibrary(std::map<std::string, std::string> files) : files_(std::move(files)) {}

const ShaderLibrary& ShaderLibrary::embedded() {
    static const ShaderLibrary library(embeddedShaderFiles());
    return library;
}

void ShaderLibrary::append(const std::string& name, Source& out, std::vector<std::string>& done, int depth) const {
    if (depth > 16) throw core::Error("shader include nesting too deep at " + name);
    const auto it = files_.find(name);
    if (it == files_.end()) throw core::Error("shader file '" + name + "' not found");
    if (std::find(done.begin(), done.end(), name) != done.end()) return;
    done.push_back(name);
    // Each file gets its own block of line numbers (file k: k * kLineBlock + line), because
    // Mesa reports every location in source string 0 whatever #line says about strings.
    const int fileIndex = int(std::find(out.files.begin(), out.files.end(), name) - out.files.begin());
    if (fileIndex == int(out.files.size())) out.files.push_back(name);
    auto begin = [&](int line) { out.strings.push_back("#line " + std::to_string(fileIndex * kLineBlock + line) + "\n"); };
    begin(1);
    std::istringstream in(it->second);
    std::string line;
    int number = 0;
    static const std::regex include(R"re(^\s*#\s*include\s+"([^"]+)")re");
    while (std::getline(in, line)) {
        ++number;
        if (line.rfind("#version", 0) == 0) {  // expand() writes it once, first
            out.strings.back() += "\n";
            continue;
        }
        std::smatch m;
        if (std::regex_search(line, m, include)) {
            append(m[1].str(), out, done, depth + 1);
            begin(number + 1);
            continue;
        }
        out.strings.back() += line + "\n";
    }
}

ShaderLibrary::Source ShaderLibrary::expand(const std::string& name, const std::vector<std::string>& defines) const {
    Source out;
    out.strings.push_back("#version 450\n");
    out.files.push_back("(defines)");  // file 0: the #version and #define lines
    for (const auto& d : defines) out.strings.back() += "#define " + d + "\n";
    std::vector<std::string> done;
    append(name, out, done, 0);
    return out;
}

std::string ShaderLibrary::Source::text() const {
    std::string t;
    for (const auto& s : strings) t += s;
    return t;
}

std::string ShaderLibrary::mapLog(const std::string& log, const Source& source) {
    static const std::regex mesa(R"((\d+):(\d+)\((\d+)\))");
    static const std::regex nvidia(R"((\d+)\((\d+)\))");
    auto where = [&](const std::string& lineText) {
        const long global = std::stol(lineText);
        const auto file = std::size_t(global / kLineBlock);
        const std::string name = file < source.files.size() ? source.files[file] : "?";
        return name + ":" + std::to_string(global % kLineBlock);
    };
    std::string out, line;
    std::istringstream in(log);
    while (std::getline(in, line)) {
        std::smatch m;
        if (std::regex_search(line, m, mesa)) line = m.prefix().str() + where(m[2].str()) + m.suffix().str();
        else if (std::regex_search(line, m, nvidia)) line = m.prefix().str() + where(m[2].str()) + m.suffix().str();
        out += line + "\n";
    }
    return out;
}

}  // namespace hvx::render
