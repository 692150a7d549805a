# SPDX-License-Identifier: Apache-2.0
# Embeds the GLSL ES sources of shaders/ into a generated C++ source at build time.
# The generated file is not committed; each shader keeps its file name so that compile
# errors can be reported as `<file>:<line>`.
function(navmap_embed_shaders target)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  set(out ${CMAKE_CURRENT_BINARY_DIR}/navmap_shaders.cpp)
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${out} "-DSOURCES=${ARG_SOURCES}"
            -P ${PROJECT_SOURCE_DIR}/cmake/EmbedShaders.cmake
    DEPENDS ${ARG_SOURCES} ${PROJECT_SOURCE_DIR}/cmake/EmbedShaders.cmake
    COMMENT "Embedding shaders"
    VERBATIM)
  add_library(${target} STATIC ${out})
  target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR}/shaders/include)
  target_link_libraries(${target} PRIVATE navmap_warnings)
endfunction()
