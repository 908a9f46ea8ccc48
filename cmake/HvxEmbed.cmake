# hvx_embed_files(OUT_VAR FUNCTION name NAMESPACE ns COMMENT text FILES ...): at build time,
# writes a .cpp that defines `ns::name()` returning the files' contents by base name
# (cmake/EmbedFiles.cmake), and sets OUT_VAR to its path for add_library.
function(hvx_embed_files out_var)
  cmake_parse_arguments(E "" "FUNCTION;NAMESPACE;COMMENT" "FILES" ${ARGN})
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${E_FUNCTION}.cpp)
  string(REPLACE ";" "|" list "${E_FILES}")
  add_custom_command(OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} "-DFILES=${list}" -DNAMESPACE=${E_NAMESPACE}
            -DFUNCTION=${E_FUNCTION} -P ${PROJECT_SOURCE_DIR}/cmake/EmbedFiles.cmake
    DEPENDS ${E_FILES} ${PROJECT_SOURCE_DIR}/cmake/EmbedFiles.cmake
    COMMENT "${E_COMMENT}" VERBATIM)
  set(${out_var} ${out} PARENT_SCOPE)
endfunction()
