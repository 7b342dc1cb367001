# The data side of out-of-core rendering: the prepared scene format, its writer and reader, `chcrt prepare` and the
# host subtree store. The tracing side (GPU subtree cache, CHC+RT over it) is culling/outofcore/.
chcrt_add_library(chcrt_outofcore
  outofcore/chs_checksum.cpp
  outofcore/chs_writer.cpp
  outofcore/compact_subtree.cpp
  outofcore/chs_file.cpp
  outofcore/lod_proxies.cpp
  outofcore/prepare.cpp
  outofcore/subtree_store.cpp
  outofcore/gpu_cache_slots.cpp
)
target_link_libraries(chcrt_outofcore PUBLIC chcrt_bvh chcrt_scene chcrt_procedural chcrt_core
  PRIVATE meshoptimizer::meshoptimizer)
