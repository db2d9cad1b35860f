# `ikebana lesson`, end to end: the shipped lessons listed and valid, a broken lesson refused by its
# fields, an arrangement scored with its criteria, a refused output left untouched.
include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
set(out ${WORK}/cli_lesson)
file(REMOVE_RECURSE ${out})
file(MAKE_DIRECTORY ${out})

expect_success("lesson list" "sogetsu_basic_upright      Sogetsu   Basic Upright Style (moribana) (shin, soe, hikae)" ${IKEBANA} lesson list)
expect_success("lesson list --json" "\"id\": \"ohara_rising_form\"" ${IKEBANA} lesson list --json)
file(GLOB lessons ${ASSETS}/lessons/*.json)
expect_success("lesson check on every shipped lesson" "ikenobo_shoka_shofutai.json: ok (ikenobo_shoka_shofutai: shin, soe, tai; 3 rule(s))" ${IKEBANA} lesson check ${lessons})

# A broken lesson: every problem named by its path, nothing else said to be fine.
file(READ ${ASSETS}/lessons/sogetsu_basic_upright.json upright)
string(REPLACE "\"target\": 15," "\"target\": 150," broken "${upright}")
string(REPLACE "\"of\": \"shin\"" "\"of\": \"tai\"" broken "${broken}")
file(WRITE ${out}/broken_lesson.json "${broken}")
expect_refusal("a lesson with a tilt beyond 90 degrees" "broken_lesson.json: /main_stems/0/tilt_deg/target: expected a number in [0, 90], got 150"
               ${IKEBANA} lesson check ${out}/broken_lesson.json)
expect_refusal("a lesson whose length follows an unknown role"
               "broken_lesson.json: /main_stems/1/length/of: expected \"container_size\", \"container_height\" or the role of an earlier main stem, got \"tai\""
               ${IKEBANA} lesson check ${out}/broken_lesson.json)
expect_refusal("a lesson id that is a path outside the lessons" "no lesson \"..\"" ${IKEBANA} lesson model ..)

# Scoring: the measured arrangement in every band, then the same with shin at 45 degrees. Its one
# jushi hides half the kenzan; hikae, low in front, hides more but is a main stem, and in Sogetsu the
# jushi hide the kenzan (issue 41): the rule is not met.
set(fixtures ${CMAKE_CURRENT_LIST_DIR}/fixtures/arrangements)
expect_success("an arrangement inside every band" "RESULT: 96.5 / 100 (sogetsu_basic_upright)"
               ${IKEBANA} lesson score sogetsu_basic_upright --arrangement ${fixtures}/sogetsu_upright_measured.json --json ${out}/result.json)
file(READ ${out}/result.json result)
string(JSON roles_given GET "${result}" arrangement stems 0 role)
if(NOT roles_given STREQUAL "shin")
  message(FATAL_ERROR "the result's arrangement gives the first stem the role '${roles_given}', not shin")
endif()
expect_success("the jushi rule's tip" "rule      the kenzan still shows from the front: the supporting stems hide 48 % of its width, the form wants 80 %: add a low supporting stem leaning toward the viewer, in front of its left end"
               ${IKEBANA} lesson score sogetsu_basic_upright --arrangement ${fixtures}/sogetsu_upright_measured.json)
expect_success("a result scored again" "RESULT: 96.5 / 100 (sogetsu_basic_upright)"
               ${IKEBANA} lesson score sogetsu_basic_upright --arrangement ${out}/result.json)
expect_success("shin at 45 degrees" "shin      16.0 / 30   shin: 45° from vertical, the form wants 15° ±10°, 20° outside it: raise it 30° toward upright"
               ${IKEBANA} lesson score sogetsu_basic_upright --arrangement ${fixtures}/sogetsu_upright_shin45.json)
expect_success("shin at 45 degrees, as JSON" "\"score\": 84.2" ${IKEBANA} lesson score sogetsu_basic_upright --arrangement ${fixtures}/sogetsu_upright_shin45.json --json -)
expect_success("free practice against the sample" "RESULT: " ${IKEBANA} lesson score free_practice --arrangement ${fixtures}/sogetsu_upright_measured.json)
file(READ ${fixtures}/sogetsu_upright_measured.json measured)
string(REPLACE "{\"species\": \"willow_branch\"" "{\"role\": \"tai\", \"species\": \"willow_branch\"" tai "${measured}")
file(WRITE ${out}/tai.json "${tai}")
expect_refusal("an arrangement with a role the lesson has not"
               "ikebana lesson score: tai.json: /stems/0/role: \"tai\" is not a role of sogetsu_basic_upright (shin, soe, hikae, or supporting)"
               ${IKEBANA} lesson score sogetsu_basic_upright --arrangement ${out}/tai.json)

# The output is checked before anything is scored: a link is refused and its target untouched.
file(WRITE ${out}/target.txt "keep")
file(CREATE_LINK ${out}/target.txt ${out}/link.json SYMBOLIC)
expect_refusal("--json onto a symbolic link" "link.json: is a symbolic link, not a file; refusing to write to it"
               ${IKEBANA} lesson score sogetsu_basic_upright --arrangement ${fixtures}/sogetsu_upright_measured.json --json ${out}/link.json)
file(READ ${out}/target.txt kept)
if(NOT kept STREQUAL "keep")
  message(FATAL_ERROR "--json wrote through a symbolic link")
endif()

# The demonstration, headless: its steps said, its arrangement scored.
expect_success("the Ohara demonstration" "subject: cut it to 438 mm (425 above the kenzan, 13 in the pins)" ${IKEBANA} lesson demo ohara_rising_form)
expect_refusal("a tilt for a role the form has not" "ikebana lesson demo: --tilt: 'tai=45': expected ROLE=DEGREES with a role of sogetsu_basic_upright and 0-90 degrees"
               ${IKEBANA} lesson demo sogetsu_basic_upright --tilt tai=45)
expect_refusal("a tilt past level" "ikebana lesson demo: --tilt: 'shin=120': expected ROLE=DEGREES with a role of sogetsu_basic_upright and 0-90 degrees"
               ${IKEBANA} lesson demo sogetsu_basic_upright --tilt shin=120)
# A demonstration on record replays to the same state (the window records its own sessions: cli_lesson_window).
file(REMOVE_RECURSE ${out}/session)
expect_success("a demonstration on record" "the session is on record in ${out}/session" ${IKEBANA} lesson demo sogetsu_basic_upright --record ${out}/session)
expect_success("its replay" "(as recorded)" ${IKEBANA} lesson replay ${out}/session)
expect_success("its replay as `ikebana replay --json`" "(as recorded)" ${IKEBANA} replay ${out}/session --json ${out}/replayed.json)
# A recording whose state is changed after the fact parts from it, and says where.
file(READ ${out}/session/session.json recorded)
string(REGEX REPLACE "\"sim:components::StemPoints\": \"[0-9a-f]+\"" "\"sim:components::StemPoints\": \"0000000000000000\"" tampered "${recorded}")
string(REGEX REPLACE "\"state_hash\": \"[0-9a-f]+\"" "\"state_hash\": \"0000000000000000\"" tampered "${tampered}")
file(WRITE ${out}/session/session.json "${tampered}")
expect_refusal("a recording whose final state is not the replay's" "ikebana replay: the replay does not reach the recorded session: score"
               ${IKEBANA} replay ${out}/session --json ${out}/replayed.json)
file(WRITE ${out}/session/session.json "${recorded}")
file(WRITE ${out}/session/commands.csv "100,cut,1,0.3\n50,cut,1,0.2\n")
expect_refusal("a replay with its cuts out of order" "commands.csv: line 2: expected time_us,cut,hand,keep_length_m" ${IKEBANA} lesson replay ${out}/session)
expect_refusal("a folder with no recording" "ikebana replay: ${out}/nothing/session.json" ${IKEBANA} replay ${out}/nothing --json -)
expect_refusal("a folder with no recording, in the window" "ikebana replay: ${out}/nothing/session.json" ${IKEBANA} replay ${out}/nothing)
expect_refusal("a display the replay window does not know" "ikebana replay: --stereo: stereo mode 'tv': expected sbs, rows, anaglyph or mono"
               ${IKEBANA} replay ${out}/session --stereo tv)
expect_refusal("the window's session on record" "ikebana lesson demo: --record records the headless demonstration"
               ${IKEBANA} lesson demo sogetsu_basic_upright --window --record ${out}/never)
expect_refusal("a demonstration of free practice" "ikebana lesson demo: free_practice copies its scene's sample; it has no form to demonstrate"
               ${IKEBANA} lesson demo free_practice)

# A session's report (issue 41): the demonstration recorded and stored, then its page as PNG and PDF.
expect_success("a demonstration recorded and stored" "stored as session 1 in ${out}/report.sqlite"
               ${IKEBANA} lesson demo ohara_rising_form --record ${out}/ohara_recording --db ${out}/report.sqlite)
expect_success("its report" "wrote ${out}/ohara_report/report.png and ${out}/ohara_report/report.pdf"
               ${IKEBANA} report ${out}/ohara_recording --out ${out}/ohara_report --db ${out}/report.sqlite)
foreach(page report.png report.pdf)
  if(NOT EXISTS ${out}/ohara_report/${page})
    message(FATAL_ERROR "the report's ${page} was not written")
  endif()
endforeach()
expect_refusal("a report of a folder that is not a recording" "ikebana report: ${out}/ohara_report: not a session's recording (no session.json in it)"
               ${IKEBANA} report ${out}/ohara_report --out ${out}/never_report --db ${out}/report.sqlite)
if(EXISTS ${out}/never_report)
  message(FATAL_ERROR "a refused report made its folder")
endif()
