# `cmake --install build [--prefix DIR]`: the gvr command, the static libraries, their
# headers (under include/gvr, by folder) and gvrConfig.cmake, so that a project outside
# this tree can find_package(gvr) and link gvr::gvr (examples/installed/).
include(CMakePackageConfigHelpers)

# gvr::gvr is everything: the readers and writers, the fit, the renderers, the
# workflows that combine them (without the MPI team) and the benchmark runner.
add_library(gvr_library INTERFACE)
target_link_libraries(gvr_library INTERFACE gvr_workflow gvr_bench)
set_target_properties(gvr_library PROPERTIES EXPORT_NAME gvr)
set_target_properties(gvr_pipeline PROPERTIES EXPORT_NAME pipeline)
set_target_properties(gvr_io PROPERTIES EXPORT_NAME io)
set_target_properties(gvr_render PROPERTIES EXPORT_NAME render)
set_target_properties(gvr_bench PROPERTIES EXPORT_NAME bench)
set_target_properties(gvr_workflow PROPERTIES EXPORT_NAME workflow)
set_target_properties(gvr_nifti PROPERTIES EXPORT_NAME nifti)

install(TARGETS gvr RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS gvr_library gvr_pipeline gvr_io gvr_render gvr_workflow gvr_bench gvr_nifti EXPORT gvrTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
# Headers keep their folder, as the sources include them ("pipeline/Fitter.h").
foreach(_folder pipeline io io/formats io/asset io/guard render workflow bench)
  file(GLOB _gvr_headers CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/${_folder}/*.h)
  list(FILTER _gvr_headers EXCLUDE REGEX "/MpiTeam\\.h$")  # its library, gvr_mpi_team, is not installed
  install(FILES ${_gvr_headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/gvr/${_folder})
endforeach()

set(_gvr_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/gvr)
install(EXPORT gvrTargets NAMESPACE gvr:: DESTINATION ${_gvr_cmake_dir})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/gvrConfig.cmake.in ${PROJECT_BINARY_DIR}/gvrConfig.cmake
                              INSTALL_DESTINATION ${_gvr_cmake_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/gvrConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/gvrConfig.cmake ${PROJECT_BINARY_DIR}/gvrConfigVersion.cmake
              ${CMAKE_CURRENT_LIST_DIR}/LibraryDependencies.cmake
        DESTINATION ${_gvr_cmake_dir})
