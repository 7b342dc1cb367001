chcrt_add_library(chcrt_render
  render/render_settings.cpp
  render/camera_math.cpp
  render/scene_gpu.cpp
  render/frame_targets.cpp
  render/trace_pass.cpp
  render/trace_stage.cpp
  render/bvh_tracer.cpp
  render/renderer.cpp
  render/hit_comparison.cpp
)
target_link_libraries(chcrt_render PUBLIC chcrt_gl chcrt_bvh chcrt_scene chcrt_core)
