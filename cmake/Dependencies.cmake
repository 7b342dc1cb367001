# Third-party dependencies, all from Debian 12 packages (scripts/setup.sh installs them).
find_package(Threads REQUIRED)
find_package(glm REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(embree 3.13 REQUIRED)
find_package(meshoptimizer 0.18 REQUIRED) # Debian's libmeshoptimizer-dev: the simplifier of the LOD proxies (prepare)
find_package(PkgConfig REQUIRED)
# libEGL (glvnd) is the one GL library the headless commands link; OSMesa is opened with dlopen for `--gl osmesa`
# (renderer/gl/context_osmesa.cpp), so only its header is needed here.
pkg_check_modules(EGL REQUIRED IMPORTED_TARGET egl)
find_path(OSMESA_INCLUDE_DIR GL/osmesa.h REQUIRED)

# Image files: OpenImageIO when CHCRT_WITH_OIIO is on (the default), else the built-in codec alone. The built-in
# codec (stb for PNG/JPEG/HDR, tinyexr for EXR; renderer/core/image_codec.h) is compiled in both builds.
if(CHCRT_WITH_OIIO)
  find_package(OpenImageIO REQUIRED)
  # Debian 12's OpenImageIO target lists /usr/include/opencv4, which does not exist without OpenCV's dev
  # package; drop it so configuration does not fail.
  get_target_property(_oiio_includes OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
  if(_oiio_includes)
    list(FILTER _oiio_includes EXCLUDE REGEX "opencv4")
    set_target_properties(OpenImageIO::OpenImageIO PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_oiio_includes}")
  endif()
endif()
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb) # Debian's libstb-dev (libstb.so.0, which tinygltf links too)
find_package(tinyexr REQUIRED)                      # Debian's libtinyexr-dev

# stb_image's header readers (renderer/scene/image_header.cpp read a texture's dimensions before tinygltf decodes it).
find_path(STB_INCLUDE_DIR stb/stb_image.h REQUIRED)

# tinygltf: Debian ships libtinygltf.so with its json and stb inside.
find_path(TINYGLTF_INCLUDE_DIR tiny_gltf.h REQUIRED)
find_library(TINYGLTF_LIBRARY tinygltf REQUIRED)
add_library(tinygltf::tinygltf UNKNOWN IMPORTED)
set_target_properties(tinygltf::tinygltf PROPERTIES IMPORTED_LOCATION "${TINYGLTF_LIBRARY}"
  INTERFACE_INCLUDE_DIRECTORIES "${TINYGLTF_INCLUDE_DIR}")

if(CHCRT_BUILD_VIEWER)
  find_package(glfw3 3.3 REQUIRED)
  pkg_check_modules(IMGUI REQUIRED IMPORTED_TARGET imgui)
endif()
if(CHCRT_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
