chcrt_add_library(chcrt_procedural
  scene/procedural/procedural.cpp
  scene/procedural/procedural_spec.cpp
  scene/procedural/mesh_builder.cpp
  scene/procedural/city.cpp
  scene/procedural/interior.cpp
  scene/procedural/plant.cpp
  scene/procedural/analytic.cpp
  scene/procedural/paths.cpp
)
target_link_libraries(chcrt_procedural PUBLIC chcrt_scene)

