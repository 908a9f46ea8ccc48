# Build-time step: writes a C++ source embedding every shader file (name -> text), so the
# executables need no shader files at run time. Invoked with -DOUT=... -DFILES=a|b|c
set(body "// Generated from the shader files by render/EmbedShaders.cmake; do not edit.\n#include <map>\n#include <string>\n\nnamespace hvx::render {\nconst std::map<std::string, std::string>& embeddedShaderFiles() {\n    static const std::map<std::string, std::string> files = {\n")
string(REPLACE "|" ";" FILES "${FILES}")
foreach(f IN LISTS FILES)
  file(READ "${f}" text)
  get_filename_component(name "${f}" NAME)
  string(APPEND body "        {\"${name}\", R\"hvx_glsl(${text})hvx_glsl\"},\n")
endforeach()
string(APPEND body "    };\n    return files;\n}\n}  // namespace hvx::render\n")
file(WRITE "${OUT}.tmp" "${body}")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different "${OUT}.tmp" "${OUT}")
