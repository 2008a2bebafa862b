# A command as a user meets it: both its exit status and what it prints must be as expected
# (ctest's PASS_REGULAR_EXPRESSION alone ignores the exit status). Registered through
# add_cli_test() in tests/CMakeLists.txt; by hand:
#
#   cmake -DEXPECT_EXIT=105 "-DEXPECT_OUTPUT=--frames: Value 0 not in range" -P expect.cmake -- remotetouch demo --frames 0
#
# EXPECT_EXIT: the exit status, 0 for a success or the refusal's own code.
# EXPECT_OUTPUT: a CMake regular expression that stdout and stderr together (in the order
# written) must match; as in PASS_REGULAR_EXPRESSION, '.' also matches a newline. Unlike
# PASS_REGULAR_EXPRESSION, which splits at each ';' and passes when any one part matches, the
# expression is taken whole.
if(NOT DEFINED EXPECT_EXIT OR NOT EXPECT_EXIT MATCHES "^[0-9]+$")
  message(FATAL_ERROR "expect.cmake: -DEXPECT_EXIT=<exit status> is missing or not a number ('${EXPECT_EXIT}')")
endif()
if(NOT DEFINED EXPECT_OUTPUT OR EXPECT_OUTPUT STREQUAL "")
  message(FATAL_ERROR "expect.cmake: -DEXPECT_OUTPUT=<regular expression> is missing")
endif()

# The command: every argument after "--".
set(command)
set(after_separator FALSE)
math(EXPR last "${CMAKE_ARGC} - 1")
foreach(i RANGE ${last})
  set(argument "${CMAKE_ARGV${i}}")
  if(after_separator)
    if(argument MATCHES ";")
      message(FATAL_ERROR "expect.cmake: argument '${argument}' holds a ';', which a CMake list cannot carry")
    endif()
    list(APPEND command "${argument}")
  elseif(argument STREQUAL "--")
    set(after_separator TRUE)
  endif()
endforeach()
if(NOT command)
  message(FATAL_ERROR "expect.cmake: no command after '--'")
endif()

execute_process(COMMAND ${command} RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE output)
# The output first, as ctest shows it for a plain test.
message("${output}")
string(REPLACE ";" " " shown "${command}")
if(NOT "${status}" STREQUAL "${EXPECT_EXIT}")
  message(FATAL_ERROR "expect.cmake: '${shown}' exited with '${status}', expected ${EXPECT_EXIT}")
endif()
if(NOT output MATCHES "${EXPECT_OUTPUT}")
  message(FATAL_ERROR "expect.cmake: the output of '${shown}' does not match\n  ${EXPECT_OUTPUT}")
endif()
message("expect.cmake: exit status ${status} and the expected output")
