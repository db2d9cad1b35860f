# Issue 20's reproductions, each with its exact input: a clear refusal naming the option, file or
# field, a normal exit code (no signal), and nothing outside the run's folder touched.
set(out ${WORK}/hostile_input)
file(REMOVE_RECURSE ${out})
file(MAKE_DIRECTORY ${out})

include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)

function(expect_intact path content)
  file(READ ${path} now)
  if(NOT now STREQUAL "${content}")
    message(FATAL_ERROR "${path} was changed: '${now}'")
  endif()
endfunction()

# Crashes and hangs
expect_refusal("a rate that rounds to 0 mHz (SIGFPE)" "rate 'render' of 0.0001 Hz is below the supported minimum of 0.001 Hz"
               ${IKEBANA} sim --rate render=1e-4 --seconds 0.1)
expect_refusal("--record on a device (filesystem_error abort)" "ikebana sim: --record: /dev/null: exists and is not a folder"
               ${IKEBANA} sim --seconds 0.1 --record /dev/null)
file(MAKE_DIRECTORY ${out}/rec)
file(WRITE ${out}/victim "keep")
file(CREATE_LINK ${out}/victim ${out}/rec/left.csv SYMBOLIC)
expect_refusal("--record through a planted link" "rec/left.csv: is a symbolic link, not a file; refusing to write to it"
               ${IKEBANA} sim --seconds 0.1 --record ${out}/rec)
expect_intact(${out}/victim "keep")

file(READ ${ASSETS}/scenes/default.json scene)
string(REPLACE "\"base_mm\": [80, -120, 0]" "\"base_mm\": [1e18, -120, 0]" far "${scene}")
file(WRITE ${out}/far.json "${far}")
expect_refusal("a flower at 1e18 mm (grid hang)" "far.json: /flowers/1/base_mm/0: expected a number in [-2000, 2000], got 1e+18"
               ${IKEBANA} sim --scene ${out}/far.json --seconds 0.1)
string(REPLACE "\"position_mm\": [-120, -60, 150]" "\"position_mm\": [1e300, -60, 150]" far_hand "${scene}")
file(WRITE ${out}/far_hand.json "${far_hand}")
expect_refusal("a hand at 1e300 mm" "far_hand.json: /hands/0/position_mm/0: expected a number in [-2000, 2000], got 1e+300"
               ${IKEBANA} sim --scene ${out}/far_hand.json --seconds 0.1)
string(REPLACE "\"seed\": 1," "\"seed\": 1, \"gravity_m_s2\": [0, 0, 1e300]," heavy "${scene}")
file(WRITE ${out}/heavy.json "${heavy}")
expect_refusal("gravity of 1e300" "heavy.json: /gravity_m_s2/2: expected a number in [-100, 100], got 1e+300"
               ${IKEBANA} sim --scene ${out}/heavy.json --seconds 0.1)
file(WRITE ${out}/far.csv "time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n0,1e15,0,0.1,0,0,0,0\n1,1e15,0,0.1,0,0,0,1\n")
expect_refusal("a scripted hand at 1e15 m" "far.csv:2:3: a position beyond the 10 m any device reaches"
               ${IKEBANA} sim --left scripted:${out}/far.csv --seconds 0.1)
expect_refusal("a trajectory that is /dev/zero" "/dev/zero: not a regular file (a device, a FIFO or a socket is never read)"
               ${IKEBANA} sim --left scripted:/dev/zero --seconds 0.1)
expect_refusal("a replay that is /dev/zero" "/dev/zero: not a regular file (a device, a FIFO or a socket is never read)"
               ${IKEBANA} sim --right replay:/dev/zero --seconds 0.1)
file(READ ${ASSETS}/species/sunflower.json sunflower)
string(REPLACE "\"meshes/sunflower_head.gltf\"" "\"/dev/zero\"" zero_mesh "${sunflower}")
file(WRITE ${out}/zero_mesh.json "${zero_mesh}")
expect_refusal("a head mesh that is /dev/zero" "/head/mesh: \"/dev/zero\" is outside zero_mesh.json's folder and the assets folder" ${IKEBANA} species check ${out}/zero_mesh.json)
execute_process(COMMAND mkfifo ${out}/fifo.json RESULT_VARIABLE made)
if(made EQUAL 0)
  expect_refusal("a scene that is a FIFO" "fifo.json: not a regular file" ${IKEBANA} sim --scene ${out}/fifo.json --seconds 0.1)
  expect_refusal("a species file that is a FIFO" "fifo.json: not a regular file" ${IKEBANA} species check ${out}/fifo.json)
  expect_refusal("render with a scene that is a FIFO" "fifo.json: not a regular file" ${IKEBANA} render --scene ${out}/fifo.json --out ${out}/never_rendered)
  if(EXISTS ${out}/never_rendered)
    message(FATAL_ERROR "render refused its scene but left an empty output folder")
  endif()
endif()

# Security: outputs that are links or devices are refused and left as they were
file(WRITE ${out}/measured.csv "flower_id,insertion,max_force_gf\nA,1,480\n")
file(WRITE ${out}/precious "keep")
file(CREATE_LINK ${out}/precious ${out}/link.csv SYMBOLIC)
expect_refusal("predict -o LINK" "ikebana predict: -o: ${out}/link.csv: is a symbolic link, not a file; refusing to write to it"
               ${IKEBANA} predict ${out}/measured.csv -o ${out}/link.csv)
expect_intact(${out}/precious "keep")
expect_refusal("predict -o a device" "ikebana predict: -o: /dev/null: is a device, not a file; refusing to write to it"
               ${IKEBANA} predict ${out}/measured.csv -o /dev/null)
expect_refusal("render --out a device" "ikebana render: --out: /dev/null: exists and is not a folder"
               ${IKEBANA} render --out /dev/null)
expect_refusal("experiment --json LINK" "ikebana experiment: --json: ${out}/link.csv: is a symbolic link" ${IKEBANA} experiment --trials 1 --json ${out}/link.csv)
expect_intact(${out}/precious "keep")
# A planted OUT.tmp link: the old writer wrote through it.
file(WRITE ${out}/victim2 "keep")
file(CREATE_LINK ${out}/victim2 ${out}/predicted.csv.tmp SYMBOLIC)
execute_process(COMMAND ${IKEBANA} predict ${out}/measured.csv -o ${out}/predicted.csv RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "predict beside a planted link failed (${rc}): ${err}")
endif()
expect_intact(${out}/victim2 "keep")

# Values that gave silently wrong results
expect_refusal("--seconds 1e13 (overflowed the timeline)" "--seconds: 1e13 s is more than the 1e12 s the microsecond timeline can hold"
               ${IKEBANA} sim --seconds 1e13)
expect_refusal("experiment --angle nan" "--angle: 'nan' is not a finite number; expected a number in [10, 90] degrees"
               ${IKEBANA} experiment --angle nan)
file(WRITE ${out}/deep.csv "flower_id,insertion,max_force_gf,depth_mm\nA,1,480,50\n")
expect_refusal("predict with a depth beyond the pins" "deep.csv:2: depth_mm: 50 mm is deeper than the kenzan's pins are tall (13 mm)"
               ${IKEBANA} predict ${out}/deep.csv -o ${out}/deep_out.csv)
file(WRITE ${out}/pins.csv "flower_id,insertion,max_force_gf,pins\nA,1,480,999\n")
expect_refusal("predict with 999 pins" "pins.csv:2: pins: 999 is more than a 7.5 mm stem at 45 degrees can touch"
               ${IKEBANA} predict ${out}/pins.csv -o ${out}/pins_out.csv)
file(WRITE ${out}/pins0.csv "flower_id,insertion,max_force_gf,pins\nA,1,480,0\n")
expect_refusal("predict with 0 pins" "pins0.csv:2: column 'pins': expected an integer in [1, 1000], got '0'"
               ${IKEBANA} predict ${out}/pins0.csv -o ${out}/pins0_out.csv)
file(WRITE ${out}/fast.csv "flower_id,insertion,max_force_gf,speed_mm_s\nA,1,480,1e8\n")
expect_refusal("a push at 100 km/s" "fast.csv:2: column 'speed_mm_s': expected a number in [0, 5000], got '1e8'"
               ${IKEBANA} predict ${out}/fast.csv -o ${out}/fast_out.csv)
string(REPLACE "\"direction\": [0.5, 0.0, 0.866]" "\"direction\": [0, 0, -1]" down "${scene}")
file(WRITE ${out}/down.json "${down}")
expect_refusal("a stem pointing down into the kenzan" "down.json: /flowers/0/direction: an inserted stem must point up out of the pins"
               ${IKEBANA} sim --scene ${out}/down.json --seconds 0.1)
string(REPLACE "\"species\": \"cherry_branch\"" "\"species\": \"no_such_flower\"" unknown "${scene}")
file(WRITE ${out}/unknown.json "${unknown}")
expect_refusal("a scene's species error" "unknown.json: /flowers/1/species: " ${IKEBANA} sim --scene ${out}/unknown.json --seconds 0.1)

# A haptic rate too low for a species is said, naming it.
execute_process(COMMAND ${IKEBANA} sim --seconds 0.1 --rate haptic=100 RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
string(FIND "${err}" "is below the" at)
string(FIND "${err}" "cherry_branch's stiffness needs" named)
if(NOT rc EQUAL 0 OR at EQUAL -1 OR named EQUAL -1)
  message(FATAL_ERROR "no warning naming the species at --rate haptic=100 (${rc}):\n${err}")
endif()
# A UTF-8 byte-order mark and CR-only lines read like any other table.
string(ASCII 239 187 191 bom)
file(WRITE ${out}/bom.csv "${bom}flower_id,insertion,max_force_gf\rA,1,480\r")
execute_process(COMMAND ${IKEBANA} predict ${out}/bom.csv -o ${out}/bom_out.csv RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "a CSV with a BOM and CR-only lines was refused (${rc}): ${err}")
endif()
# glTF: a uri escaping the mesh's folder is refused by name; a picture a material names and that is
# not there is named.
file(READ ${ASSETS}/species/sunflower.json species)
file(READ ${ASSETS}/meshes/sunflower_head.gltf head)
string(JSON pictured SET "${head}" images "[{\"uri\": \"huge.png\"}]")
string(JSON pictured SET "${pictured}" textures "[{\"source\": 0}]")
string(JSON pictured SET "${pictured}" materials "[{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}}}]")
string(JSON pictured SET "${pictured}" meshes 0 primitives 0 material 0)
string(REPLACE "\"meshes/sunflower_head.gltf\"" "\"pictured.gltf\"" pictured_species "${species}")
# (in a folder of its own: a species file is named by its id)
file(WRITE ${out}/pictured/sunflower.json "${pictured_species}")
file(WRITE ${out}/pictured/pictured.gltf "${pictured}") # beside the species: a species names only files there or shipped
expect_refusal("a head mesh whose material names a missing picture" "pictured.gltf: /images/0: \"huge.png\" could not be read (not in the mesh's folder, or not a PNG or JPEG)"
               ${IKEBANA} species check ${out}/pictured/sunflower.json)
string(JSON escaping SET "${head}" buffers 0 uri "\"/etc/passwd\"")
file(WRITE ${out}/escaping.gltf "${escaping}")
string(REPLACE "\"meshes/sunflower_head.gltf\"" "\"${out}/escaping.gltf\"" escaping_species "${species}")
file(WRITE ${out}/escaping_species.json "${escaping_species}")
expect_refusal("a glTF buffer at /etc/passwd" "escaping.gltf: /buffers/0/uri: '/etc/passwd' is refused: a mesh reads only files in its own folder"
               ${IKEBANA} species check ${out}/escaping_species.json)

# Issue 40: a lane callgrind is asked to count that is not there is named with the lanes there are.
expect_refusal("--count-lane of no lane" "ikebana sim: --count-lane: no lane 'nope' (lanes: " ${IKEBANA} sim --seconds 0.1 --count-lane nope)

message(STATUS "every hostile input is refused or handled, and nothing it pointed at was touched")
