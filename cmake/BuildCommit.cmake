# chcrt_build_commit: generated/app/build_commit.cpp, the commit the binaries are built from (app/build_info.h).
# Regenerated at every build (the commit moves without a reconfigure); the file changes only with the commit.
set(CHCRT_BUILD_COMMIT_CPP ${CMAKE_BINARY_DIR}/generated/app/build_commit.cpp)
add_custom_target(chcrt_build_commit
  COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${PROJECT_SOURCE_DIR} -DOUTPUT=${CHCRT_BUILD_COMMIT_CPP}
          -P ${PROJECT_SOURCE_DIR}/cmake/build_commit_script.cmake
  BYPRODUCTS ${CHCRT_BUILD_COMMIT_CPP}
  COMMENT "Recording the build commit"
  VERBATIM)
