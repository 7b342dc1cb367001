chcrt_add_library(chcrt_core
  core/progress.cpp
  core/frame_range.cpp
  core/image_io.cpp
  core/output_path.cpp
  core/signal_cleanup.cpp
  scene/camera_path.cpp # header-only dependency on scene.h (Camera); kept here so it builds alone
)
target_link_libraries(chcrt_core PUBLIC Threads::Threads PRIVATE OpenImageIO::OpenImageIO nlohmann_json::nlohmann_json)
