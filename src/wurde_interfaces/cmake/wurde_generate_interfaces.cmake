# wurde_generate_interfaces(<target> <interface.xml>... [DEPENDENCIES <pkg>...] [BUILTINS])
#
# Generate ROS 2 messages from WURDE interface definition files (WURDE Programming Guide ch. 3),
# the same way wurde_interfaces does for its own:
#   - at configure time, the generator (python -m wurde_idl) validates the XML files and writes
#     <X>Data.msg, <X>Info.msg and one .msg per <type> into the build directory; a refused file
#     stops the configure step with "file:line: reason";
#   - rosidl_generate_interfaces(<target> ...) builds them like any other message package;
#   - the run-time description of each interface is installed to share/<pkg>/wurde/interfaces/
#     and the package is registered in the ament index (resource type "wurde_interfaces"), so that
#     wurde_core finds the interfaces at run time.
# Editing an XML file re-runs the configure step.  Call it once per package, after
# find_package(rosidl_default_generators REQUIRED) and find_package(wurde_interfaces REQUIRED).
# It is a macro, not a function, because rosidl_generate_interfaces() is a macro whose variables
# ament_package() must see in the package's own scope.
macro(wurde_generate_interfaces target)
  cmake_parse_arguments(_wurde "BUILTINS" "" "DEPENDENCIES" ${ARGN})
  if(NOT _wurde_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "wurde_generate_interfaces(${target}): no interface XML files given")
  endif()
  find_package(Python3 REQUIRED COMPONENTS Interpreter)

  set(_wurde_xml_files "")
  foreach(_wurde_xml ${_wurde_UNPARSED_ARGUMENTS})
    get_filename_component(_wurde_abs "${_wurde_xml}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
    list(APPEND _wurde_xml_files "${_wurde_abs}")
  endforeach()
  # Re-run the generator when an interface file or the generator itself changes.
  file(GLOB _wurde_generator_sources "${WURDE_IDL_PYTHONPATH}/wurde_idl/*.py")
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
    ${_wurde_xml_files} ${_wurde_generator_sources})

  # rosidl does not regenerate a package's type hashes when a dependency's messages change, so
  # the generated .msg files name a digest of the dependencies' type descriptions: a changed
  # dependency changes them, and rosidl rebuilds this package from scratch.
  set(_wurde_dep_digest "")
  foreach(_wurde_dep ${_wurde_DEPENDENCIES})
    if(DEFINED ${_wurde_dep}_DIR)
      file(GLOB _wurde_dep_json "${${_wurde_dep}_DIR}/../msg/*.json")
      foreach(_wurde_json ${_wurde_dep_json})
        file(SHA256 "${_wurde_json}" _wurde_sum)
        string(APPEND _wurde_dep_digest "${_wurde_sum}")
      endforeach()
      set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_wurde_dep_json})
    endif()
  endforeach()
  if(NOT _wurde_dep_digest STREQUAL "")
    string(SHA256 _wurde_dep_digest "${_wurde_dep_digest}")
  endif()

  set(_wurde_out "${CMAKE_CURRENT_BINARY_DIR}/wurde_generated")
  set(_wurde_extra "")
  if(_wurde_BUILTINS)
    set(_wurde_extra "--builtins")
  endif()
  set(_wurde_pythonpath "${WURDE_IDL_PYTHONPATH}")
  if(DEFINED ENV{PYTHONPATH} AND NOT "$ENV{PYTHONPATH}" STREQUAL "")
    set(_wurde_pythonpath "${_wurde_pythonpath}:$ENV{PYTHONPATH}")
  endif()
  execute_process(
    COMMAND "${CMAKE_COMMAND}" -E env "PYTHONPATH=${_wurde_pythonpath}"
            "${Python3_EXECUTABLE}" -m wurde_idl generate --package "${PROJECT_NAME}"
            --output "${_wurde_out}" --depends-digest "${_wurde_dep_digest}"
            ${_wurde_extra} ${_wurde_xml_files}
    OUTPUT_VARIABLE _wurde_generated
    ERROR_VARIABLE _wurde_errors
    RESULT_VARIABLE _wurde_result
    OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT _wurde_result EQUAL 0)
    message(FATAL_ERROR "WURDE interface generation failed for ${PROJECT_NAME}:\n${_wurde_errors}")
  endif()

  string(REPLACE "\n" ";" _wurde_generated "${_wurde_generated}")
  set(_wurde_idl_tuples "")
  foreach(_wurde_rel ${_wurde_generated})
    list(APPEND _wurde_idl_tuples "${_wurde_out}:${_wurde_rel}")
  endforeach()
  rosidl_generate_interfaces(${target} ${_wurde_idl_tuples}
    DEPENDENCIES builtin_interfaces ${_wurde_DEPENDENCIES})

  file(READ "${_wurde_out}/interface_names.txt" _wurde_names)
  ament_index_register_resource("wurde_interfaces" CONTENT "${_wurde_names}")
  install(DIRECTORY "${_wurde_out}/wurde/interfaces" DESTINATION "share/${PROJECT_NAME}/wurde")
endmacro()
