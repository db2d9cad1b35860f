# A designer's own folder, away from the assets: what a species, scene or lesson names is looked for
# beside the file that names it, then in the assets folder; where it is in neither, the error says both
# places it looked; a species whose id is not its file's name is refused by `species check`.
set(out ${WORK}/designer_paths)
file(REMOVE_RECURSE ${out})
file(MAKE_DIRECTORY ${out}/meshes ${out}/elsewhere)

include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)

# A tulip made from the sunflower's file, with its head mesh in the designer's meshes/ folder and its
# petals and leaves the shipped ones.
file(READ ${ASSETS}/species/sunflower.json sunflower)
string(REPLACE "\"id\": \"sunflower\"" "\"id\": \"tulip\"" tulip "${sunflower}")
string(REPLACE "meshes/sunflower_head.gltf" "meshes/tulip_head.gltf" tulip "${tulip}")
file(WRITE ${out}/tulip.json "${tulip}")
expect_refusal("a head mesh in neither place"
               "tulip.json: /head/mesh: \"meshes/tulip_head.gltf\" is not at ${out}/meshes/tulip_head.gltf (beside tulip.json) nor ${ASSETS}/meshes/tulip_head.gltf (in the assets folder)"
               ${IKEBANA} species check ${out}/tulip.json)
file(COPY_FILE ${ASSETS}/meshes/sunflower_head.gltf ${out}/meshes/tulip_head.gltf)
# Checked from another working directory: the mesh is found beside the species, not beside the shell.
execute_process(COMMAND ${IKEBANA} species check ${out}/tulip.json WORKING_DIRECTORY ${out}/elsewhere
                RESULT_VARIABLE rc OUTPUT_VARIABLE said ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT said MATCHES "tulip.json: ok \\(tulip,")
  message(FATAL_ERROR "the tulip with its head beside it: exit ${rc}:\n${said}${err}")
endif()

file(WRITE ${out}/second_tulip.json "${tulip}")
expect_refusal("an id that is not the file's name"
               "second_tulip.json: /id: \"tulip\" is not the file's name (second_tulip): a scene names a species by its file's name and the simulation knows it by its id; make them agree"
               ${IKEBANA} species check ${out}/second_tulip.json)

# A scene beside the tulip names it by its file and the cherry branch by the assets' path; it runs from
# any working directory.
file(READ ${ASSETS}/scenes/default.json scene)
string(JSON scene SET "${scene}" flowers 0 species "\"tulip.json\"")
string(JSON scene SET "${scene}" flowers 1 species "\"species/cherry_branch.json\"")
file(WRITE ${out}/scene.json "${scene}")
execute_process(COMMAND ${IKEBANA} sim --scene ${out}/scene.json --seconds 0.5 WORKING_DIRECTORY ${out}/elsewhere
                RESULT_VARIABLE rc OUTPUT_VARIABLE said ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT said MATCHES "tulip" OR NOT said MATCHES "cherry_branch")
  message(FATAL_ERROR "the designer's scene: exit ${rc}:\n${said}${err}")
endif()
string(JSON lost SET "${scene}" flowers 1 species "\"nowhere/cherry.json\"")
file(WRITE ${out}/lost.json "${lost}")
expect_refusal("a scene naming a species in neither place"
               "lost.json: /flowers/1/species: \"nowhere/cherry.json\" is not at ${out}/nowhere/cherry.json (beside lost.json) nor ${ASSETS}/nowhere/cherry.json (in the assets folder)"
               ${IKEBANA} sim --scene ${out}/lost.json --seconds 0.5)

# A lesson beside the scene it copies its sample from.
file(READ ${ASSETS}/lessons/free_practice.json lesson)
string(JSON lesson SET "${lesson}" scene "\"scene.json\"")
file(WRITE ${out}/free_practice.json "${lesson}")
expect_success("a lesson naming the scene beside it" "free_practice.json: ok (free_practice:" ${IKEBANA} lesson check ${out}/free_practice.json)
file(WRITE ${out}/my_practice.json "${lesson}")
expect_refusal("a lesson whose id is not its file's name"
               "my_practice.json: /id: \"free_practice\" is not the file's name (my_practice): a lesson is found by its id, as lessons/<id>.json; make them agree"
               ${IKEBANA} lesson check ${out}/my_practice.json)
file(REMOVE ${out}/scene.json)
expect_refusal("a lesson naming a scene in neither place"
               "free_practice.json: /scene: \"scene.json\" is not at ${out}/scene.json (beside free_practice.json) nor ${ASSETS}/scene.json (in the assets folder)"
               ${IKEBANA} lesson check ${out}/free_practice.json)

message(STATUS "a designer's folder resolves beside its files, and says where it looked")
