# What every CLI refusal test expects: a refusal (exit 1 or 2, or CLI11's 105 for a bad option, never
# a signal) whose output says `expected_text`. Included by the cli_*.cmake scripts.
function(expect_refusal what expected_text)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE text ERROR_VARIABLE text TIMEOUT 600)
  if(NOT rc MATCHES "^(1|2|105)$")
    message(FATAL_ERROR "${what}: expected a refusal (exit 1, 2 or 105), got '${rc}':\n${text}")
  endif()
  string(FIND "${text}" "${expected_text}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${what}: the message does not say '${expected_text}':\n${text}")
  endif()
endfunction()

# And a success: exit 0, standard output says `expected_text`; the output is left in `said`. (A
# demonstration simulates a minute: under TSan it takes longer than a minute; ctest's own timeout
# still ends a hung one.)
function(expect_success what expected_text)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE text ERROR_VARIABLE err TIMEOUT 600)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what}: exit ${rc}:\n${text}${err}")
  endif()
  string(FIND "${text}" "${expected_text}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${what}: the output does not say '${expected_text}':\n${text}")
  endif()
  set(said "${text}" PARENT_SCOPE)
endfunction()
