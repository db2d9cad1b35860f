# `ikebana species preview` on every shipped species and on a tulip made as docs/species-format.md
# says (its own head mesh beside it): the numbers, every picture, the JSON; --watch previews again when
# the file is saved; a bad --size is named.
set(out ${WORK}/species_preview)
file(REMOVE_RECURSE ${out})
file(MAKE_DIRECTORY ${out}/flowers/meshes)

include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)

function(expect_pictures folder)
  foreach(name sheet.png stand_00.png stand_45.png stand_70.png sag.png turntable_00.png turntable_07.png)
    if(NOT EXISTS ${folder}/${name})
      message(FATAL_ERROR "species preview did not write ${folder}/${name}")
    endif()
    file(SIZE ${folder}/${name} bytes)
    if(bytes LESS 1500)
      message(FATAL_ERROR "${folder}/${name} is ${bytes} bytes: an empty picture?")
    endif()
  endforeach()
endfunction()

file(GLOB shipped ${ASSETS}/species/*.json)
foreach(file ${shipped})
  get_filename_component(id ${file} NAME_WE)
  expect_success("species preview ${id}" "set at 0 deg: " ${IKEBANA} species preview ${file} --out ${out}/${id} --size 160x200 --json ${out}/${id}.json)
  expect_pictures(${out}/${id})
  file(READ ${out}/${id}.json json)
  string(JSON species GET "${json}" species)
  string(JSON n LENGTH "${json}" stands)
  string(JSON drop GET "${json}" sag tip_drop_mm)
  if(NOT species STREQUAL id OR NOT n EQUAL 3)
    message(FATAL_ERROR "${id}.json: species ${species}, ${n} stand trials:\n${json}")
  endif()
endforeach()

# The docs' worked example: a tulip in a folder of its own, its head mesh beside it.
file(READ ${ASSETS}/species/chrysanthemum.json chrysanthemum)
string(REPLACE "\"id\": \"chrysanthemum\"" "\"id\": \"tulip\"" tulip "${chrysanthemum}")
string(REPLACE "meshes/chrysanthemum_head.gltf" "meshes/tulip_head.gltf" tulip "${tulip}")
file(WRITE ${out}/flowers/tulip.json "${tulip}")
file(COPY_FILE ${ASSETS}/meshes/chrysanthemum_head.gltf ${out}/flowers/meshes/tulip_head.gltf)
expect_success("species check on the tulip" "tulip.json: ok (tulip," ${IKEBANA} species check ${out}/flowers/tulip.json)
expect_success("species preview on the tulip" "held level by its base" ${IKEBANA} species preview ${out}/flowers/tulip.json --out ${out}/tulip --size 160x200)
expect_pictures(${out}/tulip)

# --watch: a save previews again; two previews, then it stops (--passes).
# The file is saved once the first preview is done and the watch has begun (however slow the machine).
execute_process(COMMAND sh -c "'${IKEBANA}' species preview '${out}/flowers/tulip.json' --out '${out}/watched' --size 96x128 --turns 1 --watch --passes 2 > '${out}/watch.txt' 2>&1 & p=$!; i=0; while ! grep -q watching '${out}/watch.txt' && [ $i -lt 1200 ]; do sleep 0.1; i=$((i+1)); done; sleep 0.3; touch '${out}/flowers/tulip.json'; wait $p"
                RESULT_VARIABLE rc TIMEOUT 300)
file(READ ${out}/watch.txt said)
set(err "")
string(REGEX MATCHALL "held level by its base" previews "${said}")
list(LENGTH previews n)
if(NOT rc EQUAL 0 OR NOT n EQUAL 2 OR NOT said MATCHES "tulip.json changed:")
  message(FATAL_ERROR "--watch: exit ${rc}, ${n} preview(s):\n${said}${err}")
endif()

expect_refusal("--watch with JSON on standard output" "ikebana species preview: --watch writes a JSON document each preview; with --json - they would run together: give --json a file"
               ${IKEBANA} species preview ${out}/flowers/tulip.json --out ${out}/never --watch --json -)
# --json -: standard output is one JSON document (the words go to standard error).
execute_process(COMMAND ${IKEBANA} species preview ${out}/flowers/tulip.json --out ${out}/json_out --size 64x80 --turns 1 --json -
                RESULT_VARIABLE rc OUTPUT_VARIABLE json ERROR_VARIABLE words)
string(JSON species ERROR_VARIABLE bad GET "${json}" species)
if(NOT rc EQUAL 0 OR bad OR NOT species MATCHES "^tulip$" OR NOT words MATCHES "held level by its base")
  message(FATAL_ERROR "--json -: exit ${rc}, species '${species}' (${bad}):\n${json}\n${words}")
endif()
# A species file not named .json is still that file, not an id.
file(COPY_FILE ${out}/flowers/tulip.json ${out}/flowers/tulip.species)
expect_success("a species file not named .json" "tulip (${out}/flowers/tulip.species, 300 mm)" ${IKEBANA} species preview ${out}/flowers/tulip.species --out ${out}/species_suffix --size 64x80 --turns 1)
expect_refusal("a size that is not WIDTHxHEIGHT" "ikebana species preview: --size '640': expected WIDTHxHEIGHT, each 16-4096 pixels (e.g. 480x640)"
               ${IKEBANA} species preview ${out}/flowers/tulip.json --out ${out}/never --size 640)
message(STATUS "species preview works on every shipped species and on the docs' tulip")
