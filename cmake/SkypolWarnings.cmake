# Warnings on for the project's own targets; third-party headers come in as SYSTEM includes.
add_library(skypol_warnings INTERFACE)
target_compile_options(skypol_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
  -Wnon-virtual-dtor -Wold-style-cast -Wcast-align -Woverloaded-virtual
  -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough
  # GCC 12 reports impossible overlaps inside std::string at -O3 (GCC bug 105329): not our code.
  -Wno-restrict
  # GCC 12 also reports use-after-free inside Eigen's aligned_free at -O3 (GCC bug 104075 family).
  -Wno-use-after-free)
option(SKYPOL_WERROR "Treat warnings as errors" ON)
if(SKYPOL_WERROR)
  target_compile_options(skypol_warnings INTERFACE -Werror)
endif()

# The source tree's path reaches the tests through a generated header, never a -D flag: ccache's
# base_dir rewrites an absolute path in a -D flag relative to the build directory, so a checkout
# elsewhere (a CI clone, a git worktree) would be served objects that name another checkout's scenes.
# The header's contents (the path itself) are part of ccache's hash.
file(CONFIGURE OUTPUT ${PROJECT_BINARY_DIR}/generated/skypol_source_dir.h
     CONTENT "#pragma once\n#define SKYPOL_SOURCE_DIR \"@PROJECT_SOURCE_DIR@\"\n" @ONLY)

# skypol_add_test(NAME module/foo_test SOURCES ... LIBS ... [SLOW]): one Catch2 executable per module
# test, labelled `quick`, or `slow` with SLOW (skypol_label_test).
function(skypol_add_test)
  cmake_parse_arguments(T "SLOW" "NAME" "SOURCES;LIBS" ${ARGN})
  string(REPLACE "/" "_" _target "${T_NAME}")
  add_executable(${_target} ${T_SOURCES})
  target_link_libraries(${_target} PRIVATE skypol_catch_main ${T_LIBS} skypol_warnings)
  target_compile_options(${_target} PRIVATE -include ${PROJECT_BINARY_DIR}/generated/skypol_source_dir.h)
  add_test(NAME ${T_NAME} COMMAND ${_target})
  set_tests_properties(${T_NAME} PROPERTIES ENVIRONMENT "SKYPOL_BIN=$<TARGET_FILE:skypol>")
  if(T_SLOW)
    skypol_label_test(${T_NAME} SLOW)
  else()
    skypol_label_test(${T_NAME})
  endif()
endfunction()

# skypol_label_test(NAME [SLOW]): the test's ctest label. `quick`: the tests `scripts/test --quick`
# runs, together under a minute on two cores; `slow`: the end-to-end runs and the long estimator
# tests, which only the whole suite (`scripts/test`, CI) runs. Every test has one of the two
# (tests/CMakeLists.txt checks it).
function(skypol_label_test name)
  cmake_parse_arguments(L "SLOW" "" "" ${ARGN})
  if(L_SLOW)
    set_tests_properties(${name} PROPERTIES LABELS slow)
  else()
    set_tests_properties(${name} PROPERTIES LABELS quick)
  endif()
  set_property(GLOBAL APPEND PROPERTY SKYPOL_LABELLED_TESTS ${name})
endfunction()
