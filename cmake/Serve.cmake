# `megavox serve` (serve/): the job pool over the C API and the HTTP routes on cpp-httplib (Debian's
# libcpp-httplib-dev, a compiled library: its pkg-config flags select the build it was compiled as).
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)
# The OpenAPI document is compiled in; editing it reconfigures.
file(READ ${CMAKE_SOURCE_DIR}/serve/openapi.json MV_OPENAPI_JSON)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/serve/openapi.json)
configure_file(${CMAKE_SOURCE_DIR}/cmake/openapi.cpp.in ${CMAKE_BINARY_DIR}/serve_gen/openapi.cpp @ONLY)
add_library(megavox_serve STATIC
  serve/job_request.cpp
  serve/data_path.cpp
  serve/job_pool.cpp
  serve/http_api.cpp
  ${CMAKE_BINARY_DIR}/serve_gen/openapi.cpp)
target_include_directories(megavox_serve PUBLIC ${CMAKE_SOURCE_DIR})
target_link_libraries(megavox_serve PUBLIC megavox_capi nlohmann_json::nlohmann_json PRIVATE PkgConfig::HTTPLIB)
target_sources(megavox PRIVATE cli/cmd_serve.cpp)
target_link_libraries(megavox PRIVATE megavox_serve)
