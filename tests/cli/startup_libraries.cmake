# skypol starts without OpenImageIO (docs/architecture.md: it is a module, loaded by the commands
# that need it): the executable names no OpenImageIO library, and `skypol --help` maps none. The
# module itself is where OpenImageIO is. No timing: what the loader maps is what start-up costs.
# cmake -DSKYPOL=… -DMODULE=… -P startup_libraries.cmake
foreach(var SKYPOL MODULE)
  if(NOT EXISTS "${${var}}")
    message(FATAL_ERROR "${var} not found: ${${var}}")
  endif()
endforeach()
execute_process(COMMAND readelf -d "${SKYPOL}" OUTPUT_VARIABLE needed RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "readelf -d ${SKYPOL} failed")
endif()
if(needed MATCHES "OpenImageIO")
  message(FATAL_ERROR "skypol links OpenImageIO directly; it must come only through skypol_oiio.so:\n${needed}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E env LD_DEBUG=libs "${SKYPOL}" --help
                OUTPUT_QUIET ERROR_VARIABLE loaded RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "skypol --help failed")
endif()
if(loaded MATCHES "libOpenImageIO")
  message(FATAL_ERROR "skypol --help loads OpenImageIO")
endif()
execute_process(COMMAND readelf -d "${MODULE}" OUTPUT_VARIABLE module_needed)
if(NOT module_needed MATCHES "OpenImageIO")
  message(FATAL_ERROR "${MODULE} does not link OpenImageIO")
endif()
