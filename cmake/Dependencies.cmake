# Every dependency comes from a Debian 12 package; see .ci/install-deps.sh. All of them are
# found here, at the top level, so that cmake/ImportedFiles.cmake sees every imported target.
# The quirks worked around here are listed in ../shared/docs/build-notes.md.

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
find_package(CLI11 REQUIRED CONFIG)
find_package(nlohmann_json 3 REQUIRED CONFIG)
find_package(zfp REQUIRED CONFIG)  # needs the C language, enabled at the top level

# Debian's NIFTIConfig.cmake points at the wrong library folder, so build the target by hand.
# Only the nifti2 API is used: it reads NIfTI-1 as well, and the two APIs clash in one unit.
find_path(NIFTI_INCLUDE_DIR nifti2_io.h PATH_SUFFIXES nifti REQUIRED)
find_library(NIFTI2_LIBRARY nifti2 REQUIRED)
find_library(ZNZ_LIBRARY znz REQUIRED)
add_library(gvr_nifti INTERFACE)
target_include_directories(gvr_nifti SYSTEM INTERFACE ${NIFTI_INCLUDE_DIR})
target_link_libraries(gvr_nifti INTERFACE ${NIFTI2_LIBRARY} ${ZNZ_LIBRARY} ZLIB::ZLIB m)

# Benchmark manifests may be TOML as well as JSON.
find_package(tomlplusplus 3 REQUIRED CONFIG)

# The asset's entropy coder. Debian 12's libzstd-dev ships no CMake config.
find_package(PkgConfig REQUIRED)
pkg_check_modules(ZSTD REQUIRED IMPORTED_TARGET libzstd)

find_package(GTest REQUIRED CONFIG)
