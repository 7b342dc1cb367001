chcrt_add_library(chcrt_core
  core/progress.cpp
  core/frame_range.cpp
  core/image_io.cpp
)
target_link_libraries(chcrt_core PUBLIC OpenImageIO::OpenImageIO Threads::Threads)
