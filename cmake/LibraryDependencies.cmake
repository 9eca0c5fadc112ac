# The packages that gvr's libraries link, found the same way here and, once gvr is
# installed, by gvrConfig.cmake for projects that find_package(gvr). Debian 12 only.

# TBB must be found in config mode before OpenVDB's find module runs its own FindTBB.
find_package(TBB REQUIRED CONFIG)

list(APPEND CMAKE_MODULE_PATH /usr/lib/x86_64-linux-gnu/cmake/OpenVDB)
find_package(OpenVDB REQUIRED)
find_package(Blosc REQUIRED)
find_package(ZLIB REQUIRED)

find_package(OpenImageIO REQUIRED CONFIG)
# Debian's OIIO target lists /usr/include/opencv4 even when OpenCV is absent.
get_target_property(_oiio_includes OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
list(FILTER _oiio_includes EXCLUDE REGEX "opencv4")
set_target_properties(OpenImageIO::OpenImageIO PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_oiio_includes}")

find_package(embree 3 REQUIRED CONFIG)
find_package(GDCM REQUIRED)
find_package(nlohmann_json 3 REQUIRED CONFIG)
find_package(zfp REQUIRED CONFIG)  # needs the C language enabled in the project

# The asset's entropy coder. Debian 12's libzstd-dev ships no CMake config.
find_package(PkgConfig REQUIRED)
pkg_check_modules(ZSTD REQUIRED IMPORTED_TARGET libzstd)

# Benchmark manifests may be TOML as well as JSON.
find_package(tomlplusplus 3 REQUIRED CONFIG)
