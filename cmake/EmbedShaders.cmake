# Embeds every shader file under shaders/ (GLSL sources and the headers shared with C++) into the binary as a
# path -> text table, so build/bin/chcrt needs no shader directory at run time (CHCRT_SHADER_DIR overrides it,
# see renderer/gl/shader.h). Shader files are data, so they are collected with a CONFIGURE_DEPENDS glob; the
# table is regenerated when any of them changes or a file is added or removed.
function(chcrt_embed_shaders target shader_root)
  file(GLOB_RECURSE _files CONFIGURE_DEPENDS RELATIVE ${shader_root}
    ${shader_root}/*.glsl ${shader_root}/*.h)
  # The C++ declaration of the table itself is not a shader.
  list(REMOVE_ITEM _files embedded_shaders.h)
  list(SORT _files)
  set(_out ${CMAKE_BINARY_DIR}/generated/embedded_shaders.cpp)
  set(_abs "")
  foreach(_f IN LISTS _files)
    list(APPEND _abs ${shader_root}/${_f})
  endforeach()
  set(_list ${CMAKE_BINARY_DIR}/generated/embedded_shaders.list)
  file(CONFIGURE OUTPUT ${_list} CONTENT "${_files}")
  add_custom_command(OUTPUT ${_out}
    COMMAND ${CMAKE_COMMAND} -DSHADER_ROOT=${shader_root} -DFILE_LIST=${_list} -DOUT=${_out}
            -P ${PROJECT_SOURCE_DIR}/cmake/embed_shaders_script.cmake
    DEPENDS ${_abs} ${_list} ${PROJECT_SOURCE_DIR}/cmake/embed_shaders_script.cmake
    COMMENT "Embedding shaders")
  add_library(${target} STATIC ${_out})
  target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR})
endfunction()
