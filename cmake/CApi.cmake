# The C API (include/megavox/megavox.h, capi/): a thin layer over the C++ library, no exception crossing it.
configure_file(${CMAKE_SOURCE_DIR}/cmake/version.h.in ${CMAKE_BINARY_DIR}/include/megavox/version.h @ONLY)
add_library(megavox_capi STATIC
  capi/c_device.cpp
  capi/c_scene.cpp
  capi/c_job.cpp
  capi/scene_build.cpp
  capi/c_points.cpp
  capi/c_points_read.cpp
  capi/c_mask.cpp
  capi/c_image.cpp
  capi/scene_query.cpp)
# Its users see the public headers alone (include/, and the generated version.h); the C++ library is private.
target_include_directories(megavox_capi PUBLIC ${CMAKE_SOURCE_DIR}/include ${CMAKE_BINARY_DIR}/include
                           PRIVATE ${CMAKE_SOURCE_DIR}/capi)
target_link_libraries(megavox_capi PUBLIC Threads::Threads PRIVATE mv_core)
