# libmegavox.so (the C API alone, every other symbol hidden by cmake/megavox.map, no baseline) and what
# `cmake --install` lays out: the library, the C and C++ RAII headers, megavoxConfig.cmake with its version
# file, megavox.pc (both relative to where the tree lands, so it can move) and the CLI. The build tree gets
# its own megavoxConfig.cmake, megavoxTargets.cmake and megavox.pc at its top, pointing into the source and
# build trees, so a program can use a build without installing it; the installed copies wait in package/.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)
# The static core goes into the shared library, so its code must be position independent.
set_target_properties(megavox_capi PROPERTIES POSITION_INDEPENDENT_CODE ON)
add_library(megavox_shared SHARED capi/shared_library.cpp)
target_include_directories(megavox_shared PRIVATE ${CMAKE_SOURCE_DIR}/include ${CMAKE_BINARY_DIR}/include)
# Before 1.0 a minor version may change the ABI: the SONAME carries both (libmegavox.so.0.1).
set_target_properties(megavox_shared PROPERTIES OUTPUT_NAME megavox EXPORT_NAME megavox
  VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}
  CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON LINK_DEPENDS ${CMAKE_SOURCE_DIR}/cmake/megavox.map)
target_link_options(megavox_shared PRIVATE -Wl,--version-script=${CMAKE_SOURCE_DIR}/cmake/megavox.map)
# Every symbol resolved at link time, except in the sanitizer build: clang leaves the ASan runtime to the
# executable that loads the library.
if(NOT MEGAVOX_SANITIZE)
  target_link_options(megavox_shared PRIVATE -Wl,--no-undefined)
endif()
target_link_libraries(megavox_shared PRIVATE "$<LINK_LIBRARY:WHOLE_ARCHIVE,megavox_capi>" mv_core)
target_include_directories(megavox_shared INTERFACE
  $<BUILD_INTERFACE:${CMAKE_SOURCE_DIR}/include> $<BUILD_INTERFACE:${CMAKE_BINARY_DIR}/include>
  $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
add_library(megavox::megavox ALIAS megavox_shared)

install(TARGETS megavox_shared EXPORT megavoxTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} NAMELINK_COMPONENT Development)
install(FILES include/megavox/megavox.h include/megavox/megavox.hpp ${CMAKE_BINARY_DIR}/include/megavox/version.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/megavox)
install(TARGETS megavox RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
set(mv_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/megavox)
install(EXPORT megavoxTargets NAMESPACE megavox:: DESTINATION ${mv_cmake_dir})
export(EXPORT megavoxTargets NAMESPACE megavox:: FILE ${CMAKE_BINARY_DIR}/megavoxTargets.cmake)
configure_package_config_file(cmake/megavoxConfig.cmake.in ${CMAKE_BINARY_DIR}/package/megavoxConfig.cmake
  INSTALL_DESTINATION ${mv_cmake_dir})
configure_package_config_file(cmake/megavoxConfig.cmake.in ${CMAKE_BINARY_DIR}/megavoxConfig.cmake
  INSTALL_DESTINATION ${CMAKE_BINARY_DIR} INSTALL_PREFIX ${CMAKE_BINARY_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/megavoxConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/package/megavoxConfig.cmake ${CMAKE_BINARY_DIR}/megavoxConfigVersion.cmake
  DESTINATION ${mv_cmake_dir})
configure_file(cmake/megavox.pc.in ${CMAKE_BINARY_DIR}/package/megavox.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/package/megavox.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
# The library's folder is known only at generation time (a generator expression), hence the second step.
configure_file(cmake/megavox-build.pc.in ${CMAKE_BINARY_DIR}/package/megavox-build.pc.in @ONLY)
file(GENERATE OUTPUT ${CMAKE_BINARY_DIR}/megavox.pc INPUT ${CMAKE_BINARY_DIR}/package/megavox-build.pc.in)
