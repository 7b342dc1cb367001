chcrt_add_library(chcrt_gl
  gl/gl_loader.cpp
  gl/context.cpp
  gl/context_egl.cpp
  gl/context_osmesa.cpp
  gl/shader.cpp
  gl/shader_preprocess.cpp
  gl/program_cache.cpp
  gl/gl_objects.cpp
  gl/gl_object_count.cpp
  ${CHCRT_GL_LOADER_SOURCES}
)
target_include_directories(chcrt_gl PUBLIC ${CHCRT_GL_LOADER_INCLUDE_DIR})
target_include_directories(chcrt_gl PRIVATE ${OSMESA_INCLUDE_DIR})
# No OSMesa library: context_osmesa.cpp opens it with dlopen when `--gl osmesa` asks for it.
target_link_libraries(chcrt_gl PUBLIC chcrt_core chcrt_shaders_embedded PRIVATE PkgConfig::EGL ${CMAKE_DL_LIBS})
