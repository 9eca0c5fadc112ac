# Writes every file and folder that the imported targets point at (libraries, tools that
# config modules check, include folders) to ${CMAKE_BINARY_DIR}/imported-files.txt, one
# "target<TAB>property<TAB>path" a line. .ci/deps-audit maps them to Debian packages, so a
# package that the build needs but .ci/install-deps.sh does not name fails CI on any machine.

set(_gvr_path_properties
  IMPORTED_LOCATION IMPORTED_IMPLIB INTERFACE_INCLUDE_DIRECTORIES
  INTERFACE_SYSTEM_INCLUDE_DIRECTORIES INTERFACE_LINK_LIBRARIES)

function(_gvr_target_paths target out)
  set(lines "")
  get_target_property(configs ${target} IMPORTED_CONFIGURATIONS)
  set(properties ${_gvr_path_properties})
  if(configs)
    foreach(config IN LISTS configs)
      list(APPEND properties IMPORTED_LOCATION_${config} IMPORTED_IMPLIB_${config})
    endforeach()
  endif()
  foreach(property IN LISTS properties)
    get_target_property(values ${target} ${property})
    foreach(value IN LISTS values)
      # Generator expressions wrap paths; the audit needs only the absolute paths inside.
      string(REGEX MATCHALL "/[^;<>$:,\"]+" paths "${value}")
      foreach(path IN LISTS paths)
        if(IS_ABSOLUTE "${path}" AND EXISTS "${path}")
          string(APPEND lines "${target}\t${property}\t${path}\n")
        endif()
      endforeach()
    endforeach()
  endforeach()
  set(${out} "${lines}" PARENT_SCOPE)
endfunction()

# Imported targets are visible only in the folder that found them, which is why every
# find_package call lives in cmake/Dependencies.cmake, at the top level.
function(gvr_write_imported_files)
  get_directory_property(targets IMPORTED_TARGETS)
  set(lines "")
  foreach(target IN LISTS targets)
    _gvr_target_paths(${target} target_lines)
    string(APPEND lines "${target_lines}")
  endforeach()
  file(WRITE ${CMAKE_BINARY_DIR}/imported-files.txt "${lines}")
endfunction()
