# feticontact_pickup_tests(DIR): one ctest for every test file DIR/GROUP/NAME.test, named
# GROUP.NAME (deal.II's deal_ii_pickup_tests in spirit). run_case.py runs the file (its header
# says what to run and what to check; tests/README.md, "Adding a test"); the header lines read
# here are the test's properties:
#   # labels: L1, L2, ...        ctest labels (default: GROUP)
#   # timeout: SECONDS           TIMEOUT
#   # skip-exit: STATUS          SKIP_RETURN_CODE (the test is reported as skipped)
#   # run-serial: true           RUN_SERIAL
#   # fixtures-setup: NAME       FIXTURES_SETUP; # fixtures-required: NAME  FIXTURES_REQUIRED
#   # requires: PACKAGE          registered only if PACKAGE_FOUND (e.g. fclib)
# Every test runs in the build's tests/ folder with the environment ${MPI_ENV} and writes below
# output/GROUP/NAME.
function(feticontact_pickup_tests dir)
  file(GLOB _files CONFIGURE_DEPENDS ${dir}/*/*.test)
  set(_extra)
  if(TARGET fclib_check)
    set(_extra --fclib-check $<TARGET_FILE:fclib_check>)
  endif()
  foreach(_file ${_files})
    get_filename_component(_name ${_file} NAME_WLE)
    get_filename_component(_group ${_file} DIRECTORY)
    get_filename_component(_group ${_group} NAME)
    set(_test ${_group}.${_name})
    set(_labels ${_group})
    set(_properties)
    set(_wanted TRUE)
    file(STRINGS ${_file} _header REGEX
      "^# (labels|timeout|skip-exit|run-serial|fixtures-setup|fixtures-required|requires):")
    foreach(_line ${_header})
      string(REGEX REPLACE "^# ([a-z-]+): *(.*[^ ]) *$" "\\1" _key "${_line}")
      string(REGEX REPLACE "^# ([a-z-]+): *(.*[^ ]) *$" "\\2" _value "${_line}")
      string(REGEX REPLACE " *, *" ";" _list "${_value}")
      if(_key STREQUAL "labels")
        set(_labels "${_list}")
      elseif(_key STREQUAL "timeout")
        list(APPEND _properties TIMEOUT ${_value})
      elseif(_key STREQUAL "skip-exit")
        list(APPEND _properties SKIP_RETURN_CODE ${_value})
      elseif(_key STREQUAL "run-serial")
        list(APPEND _properties RUN_SERIAL ${_value})
      elseif(_key STREQUAL "fixtures-setup")
        list(APPEND _properties FIXTURES_SETUP "${_list}")
      elseif(_key STREQUAL "fixtures-required")
        list(APPEND _properties FIXTURES_REQUIRED "${_list}")
      elseif(_key STREQUAL "requires" AND NOT ${_value}_FOUND)
        set(_wanted FALSE)
      endif()
    endforeach()
    if(_wanted)
      add_test(NAME ${_test}
        COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/run_case.py file
                $<TARGET_FILE:feticontact> ${_file}
                ${CMAKE_CURRENT_BINARY_DIR}/output/${_group}/${_name} ${_extra}
        WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
      set_tests_properties(${_test} PROPERTIES LABELS "${_labels}" ENVIRONMENT "${MPI_ENV}"
        ${_properties})
    endif()
  endforeach()
endfunction()
