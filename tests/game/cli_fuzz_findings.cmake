# The three inputs a fuzzer crashed the program with (issue 18), made from the shipped files so that
# they stay in step with them: each must now be a clear error naming the file, with a normal exit.
#   1. a species with a number too large for a double: `species check` aborted (134)
#   2. a scene with the same in its seed: `sim --scene` aborted (134)
#   3. a glTF nesting 20,000 arrays in `extras`, named by a species' head mesh: `species check` (139)
set(out ${WORK}/fuzz_findings)
file(REMOVE_RECURSE ${out})
file(MAKE_DIRECTORY ${out})

include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)

file(READ ${ASSETS}/species/sunflower.json species)
string(REPLACE "\"length_mm\": 230" "\"length_mm\": 1e400" overflowing "${species}")
file(WRITE ${out}/overflow_sunflower.json "${overflowing}")
expect_refusal("species with 1e400" "overflow_sunflower.json: not valid JSON: number overflow parsing '1e400'"
               ${IKEBANA} species check ${out}/overflow_sunflower.json)

file(READ ${ASSETS}/scenes/default.json scene)
string(REPLACE "\"seed\": 1," "\"seed\": 1e400," overflowing "${scene}")
file(WRITE ${out}/overflow_scene.json "${overflowing}")
expect_refusal("scene with 1e400" "overflow_scene.json: not valid JSON: number overflow parsing '1e400'"
               ${IKEBANA} sim --scene ${out}/overflow_scene.json --seconds 0.1)

string(REPEAT "[" 20000 open)
string(REPEAT "]" 20000 close)
file(WRITE ${out}/deep.gltf "{\"asset\": {\"version\": \"2.0\"}, \"extras\": ${open}${close}}")
string(REPLACE "\"meshes/sunflower_head.gltf\"" "\"${out}/deep.gltf\"" deep_species "${species}")
file(WRITE ${out}/deep_head.json "${deep_species}")
expect_refusal("species whose head mesh nests 20000 deep" "deep.gltf:1:" ${IKEBANA} species check ${out}/deep_head.json)
expect_refusal("species whose head mesh nests 20000 deep" "nest deeper than 64 levels" ${IKEBANA} species check ${out}/deep_head.json)
message(STATUS "every fuzz finding is refused with a message naming its file")
