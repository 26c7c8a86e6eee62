# Every dependency comes from Debian 12's packages (scripts/packages.txt installs them).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(TBB REQUIRED)
find_package(embree 3 REQUIRED)
find_package(OpenEXR 3 REQUIRED)
find_package(OpenImageIO REQUIRED)
find_package(tomlplusplus 3 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(tinyobjloader REQUIRED)
# Named time zones (Europe/Paris) from the system tz database: Howard Hinnant's date, built on
# Debian with USE_OS_TZDB (reads /usr/share/zoneinfo, never the network).
find_package(date REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(ERFA REQUIRED IMPORTED_TARGET erfa)

# Debian's OpenImageIO config lists /usr/include/opencv4, which exists only with OpenCV installed;
# CMake refuses a missing include directory, so drop it.
get_target_property(_oiio_inc OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
list(FILTER _oiio_inc EXCLUDE REGEX "opencv4")
set_target_properties(OpenImageIO::OpenImageIO PROPERTIES
  INTERFACE_INCLUDE_DIRECTORIES "${_oiio_inc}"
  INTERFACE_SYSTEM_INCLUDE_DIRECTORIES "")

if(SKYPOL_BUILD_TESTS OR NOT DEFINED SKYPOL_BUILD_TESTS)
  find_package(Catch2 2 REQUIRED)
endif()
