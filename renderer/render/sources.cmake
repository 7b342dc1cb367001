chcrt_add_library(chcrt_render
  render/renderer.cpp
)
target_link_libraries(chcrt_render PUBLIC chcrt_gl chcrt_bvh chcrt_scene chcrt_core)
