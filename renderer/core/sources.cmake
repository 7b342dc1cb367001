chcrt_add_library(chcrt_core
  core/progress.cpp
  core/frame_range.cpp
  core/image_io.cpp
  core/image_codec_builtin.cpp
  core/output_path.cpp
  core/signal_cleanup.cpp
  core/memory_budget.cpp
  core/process_resources.cpp
  scene/camera_path.cpp # header-only dependency on scene.h (Camera); kept here so it builds alone
)
target_link_libraries(chcrt_core PUBLIC Threads::Threads PRIVATE ${CMAKE_DL_LIBS} PkgConfig::STB tinyexr::tinyexr nlohmann_json::nlohmann_json)
# Private: only image_io.cpp and the codecs see which codec the build has (so the travelling build, docs/gpu.md,
# compiles every other file exactly as the normal one and ccache reuses them); imageCodecName() tells the rest.
if(CHCRT_WITH_OIIO)
  target_sources(chcrt_core PRIVATE core/image_codec_oiio.cpp)
  target_link_libraries(chcrt_core PRIVATE OpenImageIO::OpenImageIO)
  target_compile_definitions(chcrt_core PRIVATE CHCRT_WITH_OIIO=1)
else()
  target_compile_definitions(chcrt_core PRIVATE CHCRT_WITH_OIIO=0)
endif()
