chcrt_add_library(chcrt_procedural
  scene/procedural/procedural.cpp
)
target_link_libraries(chcrt_procedural PUBLIC chcrt_scene)
