# `ikebana species preview FILE --window` (issue 15: "or a window when there is a display"), under
# xvfb-run: the numbers, the window's frames and a screenshot; with --watch a save is measured and shown
# again while the window is open; without a display it says how to get pictures instead.
cmake_minimum_required(VERSION 3.20)
set(out ${WORK}/species_preview_window)
file(REMOVE_RECURSE ${out})
file(MAKE_DIRECTORY ${out}/flowers)
include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)

expect_success("species preview --window" "set at 45 deg: " ${IKEBANA} species preview ${ASSETS}/species/sunflower.json --window --size 240x320
               --frames 12 --screenshot ${out}/window.png)
string(FIND "${said}" "screenshot in ${out}/window.png" at)
if(at EQUAL -1 OR NOT EXISTS ${out}/window.png)
  message(FATAL_ERROR "species preview --window: no screenshot:\n${said}")
endif()
file(SIZE ${out}/window.png bytes)
if(bytes LESS 4000)
  message(FATAL_ERROR "${out}/window.png is ${bytes} bytes: an empty window?")
endif()

# A save while the window is open: a second process rewrites the file (a deeper red look) after a few
# seconds (and then drains what the window prints); the window measures it again, shows a few frames
# of it and stops (--passes 2): the screenshot exists only if the save was seen.
file(READ ${ASSETS}/species/sunflower.json sunflower)
file(WRITE ${out}/flowers/sunflower.json "${sunflower}")
string(JSON changed SET "${sunflower}" look "{\"petal\": [0.9, 0.1, 0.1]}")
file(WRITE ${out}/changed.json "${changed}")
execute_process(COMMAND ${IKEBANA} species preview ${out}/flowers/sunflower.json --window --watch --passes 2 --size 240x320 --frames 100000
                        --screenshot ${out}/after_save.png
                COMMAND bash -c "sleep 6; cp '${out}/changed.json' '${out}/flowers/sunflower.json'; cat >/dev/null"
                RESULTS_VARIABLE rcs OUTPUT_VARIABLE text ERROR_VARIABLE err TIMEOUT 300)
if(NOT rcs STREQUAL "0;0")
  message(FATAL_ERROR "species preview --window --watch: exit ${rcs}:\n${text}\n${err}")
endif()
if(NOT EXISTS ${out}/after_save.png)
  message(FATAL_ERROR "species preview --window --watch: the window did not stop after the save with its screenshot:\n${err}")
endif()

# Without a display: the numbers still, then exit 3 (as `replay` without one) saying what to do instead.
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=DISPLAY --unset=WAYLAND_DISPLAY ${IKEBANA} species preview ${ASSETS}/species/sunflower.json --window
                RESULT_VARIABLE rc OUTPUT_VARIABLE text ERROR_VARIABLE err TIMEOUT 120)
string(FIND "${err}" "ikebana species preview: no display (DISPLAY is not set); without --window the preview is written as pictures (--out)" at)
if(NOT rc EQUAL 3 OR at EQUAL -1)
  message(FATAL_ERROR "species preview --window without a display: expected exit 3 and what to do instead, got ${rc}:\n${text}\n${err}")
endif()
message(STATUS "the preview window shows the flower, measures a save again, and says what to do without a display")
