# `ikebana history` end to end: a demonstration is stored and listed with its criteria, the plot is an
# image, and a damaged database is named, refused and left byte for byte as it was (by `history` and
# by a demonstration that would store into it).
include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
set(out ${WORK}/cli_history)
file(REMOVE_RECURSE ${out})
file(MAKE_DIRECTORY ${out})
set(run ${CMAKE_COMMAND} -E env XDG_DATA_HOME=${out}/data)
set(db ${out}/data/ikebana/progress.sqlite)

expect_success("history before any session" "no sessions of everyone yet in ${db}" ${run} ${IKEBANA} history)
if(EXISTS ${db})
  message(FATAL_ERROR "reading the history created ${db}")
endif()
expect_success("a demonstration is stored" "stored as session 1 in ${db} (ikebana history)"
               ${run} ${IKEBANA} lesson demo sogetsu_basic_upright --record ${out}/recording)
expect_success("a demonstration with shin at 45 degrees is stored" "stored as session 2 in ${db}"
               ${run} ${IKEBANA} lesson demo sogetsu_basic_upright --tilt shin=45)
expect_success("a demonstration told not to be stored" "RESULT: " ${run} ${IKEBANA} lesson demo ohara_rising_form --no-history)

expect_success("history as JSON" "\"sessions\"" ${run} ${IKEBANA} history --json)
string(JSON count LENGTH "${said}" sessions)
if(NOT count EQUAL 2)
  message(FATAL_ERROR "history --json lists ${count} sessions, not the 2 stored:\n${said}")
endif()
string(JSON kind GET "${said}" sessions 0 kind)
string(JSON score GET "${said}" sessions 0 score)
string(JSON recording GET "${said}" sessions 0 recording)
string(JSON criteria LENGTH "${said}" sessions 0 criteria)
string(JSON tip GET "${said}" sessions 1 criteria 1 tip)
if(NOT kind STREQUAL "demonstration" OR score LESS 90 OR NOT recording STREQUAL "${out}/recording" OR criteria LESS 9)
  message(FATAL_ERROR "the first session is not the demonstration as stored (kind ${kind}, score ${score}, recording ${recording}, ${criteria} criteria)")
endif()
string(FIND "${tip}" "shin:" at)
if(NOT at EQUAL 0)
  message(FATAL_ERROR "the second session's shin tilt tip is not stored: '${tip}'")
endif()
# The recording named in the history replays to the score stored.
expect_success("the stored session's recording replays" "as recorded" ${IKEBANA} lesson replay ${recording})
expect_success("history of one lesson and trainee" "2 session(s) of teacher, sogetsu_basic_upright in ${db}"
               ${run} ${IKEBANA} history --lesson sogetsu_basic_upright --trainee teacher)
expect_success("history of a lesson demonstrated with --no-history" "no sessions of everyone, ohara_rising_form yet"
               ${run} ${IKEBANA} history --lesson ohara_rising_form)
expect_success("history as a plot" "plot of the scores and each criterion's trend in ${out}/progress.png"
               ${run} ${IKEBANA} history --plot ${out}/progress.png)
file(READ ${out}/progress.png signature LIMIT 4 HEX)
if(NOT signature STREQUAL "89504e47")
  message(FATAL_ERROR "history --plot did not write a PNG (starts ${signature})")
endif()
expect_refusal("a plot in a format it does not draw" "ikebana history: --plot: ${out}/progress.pdf: a plot is written as .png or .svg"
               ${run} ${IKEBANA} history --plot ${out}/progress.pdf)

# A damaged database: named, refused, never written to.
file(WRITE ${out}/notes.sqlite "my notes on shin and soe\n")
file(SHA256 ${out}/notes.sqlite before)
set(left " it is left as it is (move it aside to start a new record)")
expect_refusal("history of a file that is not a database"
               "ikebana history: ${out}/notes.sqlite: not an Ikebana progress database (not an SQLite file);${left}"
               ${IKEBANA} history --db ${out}/notes.sqlite)
expect_refusal("a demonstration that would be stored in it"
               "ikebana lesson demo: --db: ${out}/notes.sqlite: not an Ikebana progress database (not an SQLite file);${left}"
               ${IKEBANA} lesson demo sogetsu_basic_upright --db ${out}/notes.sqlite)
file(SHA256 ${out}/notes.sqlite after)
if(NOT before STREQUAL after)
  message(FATAL_ERROR "the damaged file was written to")
endif()
