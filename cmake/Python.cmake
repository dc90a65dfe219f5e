# The Python module megavox (python/): pybind11 over the C API (libmegavox.so), built when Python's headers and
# pybind11 are installed (scripts/setup.sh installs them). The build tree's build/python is importable as is
# (PYTHONPATH=build/python); `cmake --install` puts the package where Debian's Python looks under the prefix
# (MEGAVOX_PYTHON_DIR). Not in a sanitizer build: an extension module would need the
# sanitizer runtime preloaded into Python.
if(MEGAVOX_SANITIZE)
  return()
endif()
# Debian's own Python, where setup.sh installs numpy and pytest, before any other python3 on the PATH.
if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3)
endif()
find_package(Python3 3.9 COMPONENTS Interpreter Development.Module)
if(Python3_FOUND)
  set(PYBIND11_FINDPYTHON ON)
  find_package(pybind11 2.6 CONFIG QUIET)
endif()
if(NOT Python3_FOUND OR NOT pybind11_FOUND)
  message(STATUS "megavox: no Python module (it needs python3-dev and pybind11-dev: scripts/setup.sh)")
  return()
endif()

set(mv_python_dir ${CMAKE_BINARY_DIR}/python/megavox)
pybind11_add_module(megavox_python MODULE
  python/src/module.cpp
  python/src/binding.cpp
  python/src/devices.cpp
  python/src/scenes.cpp
  python/src/points.cpp
  python/src/masks.cpp)
target_link_libraries(megavox_python PRIVATE megavox_shared)
# Debian's Python reads PREFIX/lib/python3/dist-packages for /usr, and lib/python3.X/dist-packages for
# /usr/local (sys.path), so those are the defaults.
if(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  set(mv_python_default lib/python3/dist-packages)
else()
  set(mv_python_default lib/python${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}/dist-packages)
endif()
set(MEGAVOX_PYTHON_DIR ${mv_python_default} CACHE STRING "Where `cmake --install` puts the package megavox, under the prefix")
set(mv_python_install ${MEGAVOX_PYTHON_DIR}/megavox)
# The installed module finds libmegavox.so beside it in PREFIX's library folder, wherever PREFIX lands.
file(RELATIVE_PATH mv_python_to_lib ${CMAKE_INSTALL_PREFIX}/${mv_python_install} ${CMAKE_INSTALL_FULL_LIBDIR})
set_target_properties(megavox_python PROPERTIES OUTPUT_NAME _megavox LIBRARY_OUTPUT_DIRECTORY ${mv_python_dir}
  INSTALL_RPATH "$ORIGIN/${mv_python_to_lib}")

file(GLOB mv_python_files CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/python/megavox/*.py
     ${CMAKE_SOURCE_DIR}/python/megavox/*.pyi ${CMAKE_SOURCE_DIR}/python/megavox/py.typed)
add_custom_target(megavox_python_files ALL
  COMMAND ${CMAKE_COMMAND} -E make_directory ${mv_python_dir}
  COMMAND ${CMAKE_COMMAND} -E copy_if_different ${mv_python_files} ${mv_python_dir}
  DEPENDS ${mv_python_files} COMMENT "The Python package megavox in ${mv_python_dir}")
add_dependencies(megavox_python megavox_python_files)

install(TARGETS megavox_python LIBRARY DESTINATION ${mv_python_install})
install(FILES ${mv_python_files} DESTINATION ${mv_python_install})
