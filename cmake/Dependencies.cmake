# Every dependency comes from a Debian 12 package; see .ci/install-deps.sh. All of them are
# found here, at the top level, so that cmake/ImportedFiles.cmake sees every imported target.
# The quirks worked around here are listed in ../shared/docs/build-notes.md.

# What the installed library needs as well: shared with gvrConfig.cmake.
include(${CMAKE_CURRENT_LIST_DIR}/LibraryDependencies.cmake)
find_package(CLI11 REQUIRED CONFIG)

# Debian's NIFTIConfig.cmake points at the wrong library folder, so build the target by hand.
# Only the nifti2 API is used: it reads NIfTI-1 as well, and the two APIs clash in one unit.
find_path(NIFTI_INCLUDE_DIR nifti2_io.h PATH_SUFFIXES nifti REQUIRED)
find_library(NIFTI2_LIBRARY nifti2 REQUIRED)
find_library(ZNZ_LIBRARY znz REQUIRED)
add_library(gvr_nifti INTERFACE)
target_include_directories(gvr_nifti SYSTEM INTERFACE ${NIFTI_INCLUDE_DIR})
target_link_libraries(gvr_nifti INTERFACE ${NIFTI2_LIBRARY} ${ZNZ_LIBRARY} ZLIB::ZLIB m)

# gvr view: the window and its HUD text.
find_package(SDL2 REQUIRED CONFIG)
find_package(SDL2_ttf REQUIRED CONFIG)

find_package(GTest REQUIRED CONFIG)

# gvr fit --bricks under mpirun: bricks handed to ranks, parts gathered on rank 0.
find_package(MPI REQUIRED COMPONENTS CXX)
