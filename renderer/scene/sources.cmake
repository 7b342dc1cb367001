chcrt_add_library(chcrt_scene
  scene/scene.cpp
  scene/mesh_utils.cpp
  scene/gltf_loader.cpp
  scene/gltf_accessors.cpp
  scene/image_header.cpp
  scene/ply_loader.cpp
  scene/obj_loader.cpp
  scene/scene_loader.cpp
)
target_link_libraries(chcrt_scene PUBLIC chcrt_core PRIVATE tinygltf::tinygltf nlohmann_json::nlohmann_json)
