# Writes OUTPUT, a CTest include file with one test for each GoogleTest suite in
# TEST_EXECUTABLE. Run after every link of gvr_tests (tests/CMakeLists.txt).
#
# One process a suite rather than one a test: each gvr_tests process spends about 0.4 s
# (more under AddressSanitizer) loading the 266 shared libraries that OpenImageIO
# brings, and with some 650 tests that start-up was a large share of CI's time.
#
# SKIP, a GoogleTest filter (A.B:C.*), names tests left out of every suite; the
# sanitizer build leaves out the few that measure release speed or memory.

execute_process(COMMAND "${TEST_EXECUTABLE}" --gtest_list_tests
  OUTPUT_VARIABLE listing RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "RegisterSuites: ${TEST_EXECUTABLE} --gtest_list_tests failed (${result})")
endif()

# Suite lines start in the first column and end in a dot ("Suite." or
# "Instance/Suite."); the indented lines under them are the tests.
string(REGEX MATCHALL "(^|\n)[A-Za-z_][^ \n]*\\." suite_lines "${listing}")
if(NOT suite_lines)
  message(FATAL_ERROR "RegisterSuites: ${TEST_EXECUTABLE} lists no test suites")
endif()

set(filter_tail "")
if(SKIP)
  set(filter_tail ":-${SKIP}")
endif()
set(content "")
foreach(line IN LISTS suite_lines)
  string(STRIP "${line}" suite_with_dot)
  string(REGEX REPLACE "\\.$" "" suite "${suite_with_dot}")
  string(APPEND content
    "add_test([==[${suite}]==] [==[${TEST_EXECUTABLE}]==] [==[--gtest_filter=${suite}.*${filter_tail}]==])\n"
    "set_tests_properties([==[${suite}]==] PROPERTIES TIMEOUT ${TIMEOUT})\n")
endforeach()
file(WRITE "${OUTPUT}" "${content}")
