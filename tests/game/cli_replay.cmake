# Record a session from the command line, replay it, compare state hashes.
set(dir "${WORK}/replay_session")
file(REMOVE_RECURSE "${dir}")
execute_process(COMMAND ${IKEBANA} sim --scene ${SCENE} --seconds 2 --hash --record ${dir}
                OUTPUT_VARIABLE live RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "recording run failed: ${rc}")
endif()
execute_process(COMMAND ${IKEBANA} sim --scene ${SCENE} --seconds 2 --hash --left replay:${dir}/left.csv --right replay:${dir}/right.csv
                OUTPUT_VARIABLE replayed RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "replay run failed: ${rc}")
endif()
string(REGEX MATCH "state-hash: [0-9a-f]+" live_hash "${live}")
string(REGEX MATCH "state-hash: [0-9a-f]+" replay_hash "${replayed}")
if(NOT live_hash OR NOT live_hash STREQUAL replay_hash)
  message(FATAL_ERROR "replay differs: '${live_hash}' vs '${replay_hash}'")
endif()
message(STATUS "replayed: ${replay_hash}")
