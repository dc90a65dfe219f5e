# The C API (include/megavox/megavox.h, capi/): a thin layer over the C++ library, no exception crossing it.
configure_file(${CMAKE_SOURCE_DIR}/cmake/version.h.in ${CMAKE_BINARY_DIR}/include/megavox/version.h @ONLY)
add_library(megavox_capi STATIC
  capi/c_device.cpp
  capi/c_scene.cpp
  capi/c_job.cpp
  capi/scene_build.cpp
  capi/c_points.cpp
  capi/c_mask.cpp
  capi/c_image.cpp)
target_include_directories(megavox_capi PUBLIC ${CMAKE_BINARY_DIR}/include PRIVATE ${CMAKE_SOURCE_DIR})
target_link_libraries(megavox_capi PUBLIC megavox_lib Threads::Threads)
