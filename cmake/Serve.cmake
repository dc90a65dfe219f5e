# `megavox serve` (serve/): the job pool over the C API and the HTTP routes on cpp-httplib (Debian's
# libcpp-httplib-dev, a compiled library: its pkg-config flags select the build it was compiled as). It sees the
# public headers alone (megavox.h, megavox.hpp): include/ and its own folder, no internal include folder.
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)
# 3D Tiles archives (.3tz) of point-cloud jobs: ZIP by minizip (libminizip-dev), the index's MD5 by libcrypto
# (libssl-dev, which cpp-httplib already depends on).
pkg_check_modules(MINIZIP REQUIRED IMPORTED_TARGET minizip)
pkg_check_modules(LIBCRYPTO REQUIRED IMPORTED_TARGET libcrypto)
# The OpenAPI document is compiled in; editing it reconfigures.
file(READ ${CMAKE_SOURCE_DIR}/serve/openapi.json MV_OPENAPI_JSON)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/serve/openapi.json)
configure_file(${CMAKE_SOURCE_DIR}/cmake/openapi.cpp.in ${CMAKE_BINARY_DIR}/serve_gen/openapi.cpp @ONLY)
add_library(megavox_serve STATIC
  serve/job_request.cpp
  serve/data_path.cpp
  serve/job_words.cpp
  serve/job_pool.cpp
  serve/job_follow.cpp
  serve/job_build.cpp
  serve/job_render.cpp
  serve/job_points.cpp
  serve/job_mask.cpp
  serve/job_open.cpp
  serve/tiles_archive.cpp
  serve/http_api.cpp
  ${CMAKE_BINARY_DIR}/serve_gen/openapi.cpp)
# Its users (the CLI) include its headers by name; it sees the C API's public headers alone (through
# megavox_capi: include/ and the generated version.h), never the C++ library.
target_include_directories(megavox_serve PUBLIC ${CMAKE_SOURCE_DIR}/serve)
target_link_libraries(megavox_serve PUBLIC megavox_capi nlohmann_json::nlohmann_json PRIVATE PkgConfig::HTTPLIB PkgConfig::MINIZIP PkgConfig::LIBCRYPTO)
target_sources(megavox PRIVATE cli/cmd_serve.cpp)
target_link_libraries(megavox PRIVATE megavox_serve)
