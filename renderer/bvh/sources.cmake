chcrt_add_library(chcrt_bvh
  bvh/bvh_builder.cpp
  bvh/bvh_stats.cpp
  bvh/cpu_tracer.cpp
)
target_link_libraries(chcrt_bvh PUBLIC chcrt_scene Threads::Threads)
