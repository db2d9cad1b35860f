# The trainee window stores each scored lesson session (run under xvfb-run): a session finished with
# Enter is in `ikebana history --json` under the trainee's name, the name is remembered for the next
# session, an app killed in the middle of a session loses none stored before it, and free practice
# against the paper's sample is stored as a lesson's is.
include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
set(out ${WORK}/cli_app_history)
file(REMOVE_RECURSE ${out})
file(MAKE_DIRECTORY ${out})
set(db ${out}/progress.sqlite)
set(app ${IKEBANA} --lesson sogetsu_basic_upright --width 480 --height 270 --db ${db})

execute_process(COMMAND ${app} --trainee "Mika Sato" --frames 20 --finish-at-frame 12
                RESULT_VARIABLE rc OUTPUT_VARIABLE text ERROR_VARIABLE err TIMEOUT 300)
string(FIND "${text}" "ikebana: stored as session 1 in ${db}" at)
if(NOT rc EQUAL 0 OR at EQUAL -1)
  message(FATAL_ERROR "the first session: exit ${rc}, not stored as session 1:\n${text}${err}")
endif()

# The second session scores at frame 12 and runs on (no --frames) until it is killed (SIGKILL, no
# chance to tidy up) once it has said that it stored the session: however slow the machine is.
string(JOIN " " killed_app ${app})
execute_process(COMMAND bash -c "${killed_app} --finish-at-frame 12 >${out}/killed.log 2>&1 & app=$!
  for i in $(seq 1 2400); do grep -q 'stored as session 2' ${out}/killed.log && break; kill -0 $app 2>/dev/null || exit 3; sleep 0.1; done
  sleep 1; kill -0 $app 2>/dev/null || exit 4; kill -9 $app; wait $app; exit 0"
                RESULT_VARIABLE rc TIMEOUT 300)
file(READ ${out}/killed.log text)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the second session was not killed mid-session after storing its Enter (${rc}; 3: it ended by itself, 4: it ended after storing):\n${text}")
endif()

# Free practice against the paper's sample is stored too.
execute_process(COMMAND ${IKEBANA} --lesson free_practice --width 480 --height 270 --db ${db} --frames 20 --finish-at-frame 12
                RESULT_VARIABLE rc OUTPUT_VARIABLE text ERROR_VARIABLE err TIMEOUT 300)
string(FIND "${text}" "ikebana: stored as session 3 in ${db}" at)
if(NOT rc EQUAL 0 OR at EQUAL -1)
  message(FATAL_ERROR "free practice: exit ${rc}, not stored as session 3:\n${text}${err}")
endif()

execute_process(COMMAND ${IKEBANA} history --db ${db} --json RESULT_VARIABLE rc OUTPUT_VARIABLE said ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "history after the killed session: exit ${rc}: ${err}")
endif()
string(JSON count LENGTH "${said}" sessions)
if(NOT count EQUAL 3)
  message(FATAL_ERROR "history lists ${count} sessions, not the finished one, the killed one's first Enter and free practice:\n${said}")
endif()
string(JSON third GET "${said}" sessions 2 lesson)
if(NOT third STREQUAL "free_practice")
  message(FATAL_ERROR "the third session is ${third}, not free_practice")
endif()
foreach(i 0 1)
  string(JSON trainee GET "${said}" sessions ${i} trainee)
  string(JSON kind GET "${said}" sessions ${i} kind)
  string(JSON criteria LENGTH "${said}" sessions ${i} criteria)
  string(JSON flowers LENGTH "${said}" sessions ${i} flowers)
  if(NOT trainee STREQUAL "Mika Sato" OR NOT kind STREQUAL "practice" OR criteria LESS 9 OR flowers LESS 3)
    message(FATAL_ERROR "session ${i}: trainee '${trainee}', kind ${kind}, ${criteria} criteria, ${flowers} flowers:\n${said}")
  endif()
endforeach()
