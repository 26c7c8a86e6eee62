# The Python module `skypol` (python/; included by the top-level CMakeLists.txt before the rooms): built by default when Debian's pybind11 (pybind11-dev,
# scripts/packages.txt) is there, skipped with a message when it is not. It is built for Debian's
# interpreter, /usr/bin/python3 (which has numpy), not whichever python3 comes first on PATH: the
# module's ABI must match the interpreter that imports it. -DSKYPOL_PYTHON=OFF skips it.
option(SKYPOL_PYTHON "Build the Python module (needs pybind11-dev)" ON)
set(SKYPOL_PYTHON_FOUND OFF)
if(SKYPOL_PYTHON)
  if(NOT DEFINED PYTHON_EXECUTABLE AND NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(PYTHON_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python the module is built for")
    set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python the module is built for")
  endif()
  find_package(pybind11 2.6 CONFIG QUIET)
  if(pybind11_FOUND)
    set(SKYPOL_PYTHON_FOUND ON)
    message(STATUS "skypol: Python module for ${PYTHON_EXECUTABLE} (Python ${PYTHON_VERSION}), pybind11 ${pybind11_VERSION}")
    set(CMAKE_POSITION_INDEPENDENT_CODE ON)
    add_compile_options(-fno-semantic-interposition)
  else()
    message(STATUS "skypol: pybind11 not found (apt-get install pybind11-dev python3-pybind11): "
                   "the Python module is not built")
  endif()
endif()
