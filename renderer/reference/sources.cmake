chcrt_add_library(chcrt_reference
  reference/embree_tracer.cpp
)
target_link_libraries(chcrt_reference PUBLIC chcrt_core PRIVATE embree)
