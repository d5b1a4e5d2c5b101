# maille_embed_glsl(<target> HEADER <name.hpp> NAMESPACE <ns> FILES <file.glsl>...)
# Generates <build>/generated/<name.hpp> (cmake/embed_glsl.cmake) holding each file as
# `inline constexpr std::string_view <file name without extension>` in namespace <ns>, regenerated
# when a file changes, and gives <target> the header and its folder. The one way shaders reach
# the binary: the GPU backend's kernels, the renderer's passes and the shared laws.
function(maille_embed_glsl target)
  cmake_parse_arguments(E "" "HEADER;NAMESPACE" "FILES" ${ARGN})
  set(dir ${CMAKE_CURRENT_BINARY_DIR}/generated)
  set(out ${dir}/${E_HEADER})
  set(paths "")
  foreach(f IN LISTS E_FILES)
    get_filename_component(abs "${f}" ABSOLUTE)
    list(APPEND paths "${abs}")
  endforeach()
  list(JOIN paths "|" joined)
  add_custom_command(OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DNAMESPACE=${E_NAMESPACE} -DFILES=${joined}
            -P ${PROJECT_SOURCE_DIR}/cmake/embed_glsl.cmake
    DEPENDS ${paths} ${PROJECT_SOURCE_DIR}/cmake/embed_glsl.cmake
    COMMENT "Embedding GLSL into ${E_HEADER}" VERBATIM)
  target_sources(${target} PRIVATE ${out})
  target_include_directories(${target} PRIVATE ${dir})
endfunction()
