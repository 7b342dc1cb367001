chcrt_add_library(chcrt_outofcore
  outofcore/chs_checksum.cpp
  outofcore/chs_writer.cpp
  outofcore/chs_file.cpp
  outofcore/prepare.cpp
  outofcore/subtree_store.cpp
  outofcore/gpu_subtree_cache.cpp
)
target_link_libraries(chcrt_outofcore PUBLIC chcrt_bvh chcrt_scene chcrt_procedural chcrt_gl chcrt_core)

# Out-of-core CHC+RT tracing (needs the culling library, defined later; CMake resolves the name at generate time).
chcrt_add_library(chcrt_outofcore_tracing
  outofcore/chs_culling_hierarchy.cpp
  outofcore/out_of_core_tracer.cpp
  outofcore/primary_resolve.cpp
)
target_link_libraries(chcrt_outofcore_tracing PUBLIC chcrt_outofcore chcrt_culling chcrt_render chcrt_gl chcrt_core)
