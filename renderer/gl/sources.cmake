chcrt_add_library(chcrt_gl
  gl/gl_loader.cpp
  gl/context.cpp
  gl/context_egl.cpp
  gl/context_osmesa.cpp
  gl/shader.cpp
  gl/shader_preprocess.cpp
  gl/gl_objects.cpp
  ${CHCRT_GL_LOADER_SOURCES}
)
target_include_directories(chcrt_gl PUBLIC ${CHCRT_GL_LOADER_INCLUDE_DIR})
target_link_libraries(chcrt_gl PUBLIC chcrt_core chcrt_shaders_embedded PRIVATE PkgConfig::EGL PkgConfig::OSMESA ${CMAKE_DL_LIBS})
