# `ikebana validate --paper` end to end: the JSON has the issue's schema, the report and its figures
# are written, and the extended species is one that `species check` and `predict --species` accept.
set(out ${WORK}/validate_paper)
file(REMOVE_RECURSE ${out})
file(MAKE_DIRECTORY ${out})
execute_process(COMMAND ${IKEBANA} validate --paper --paper-trials 3 --paper-hold-trials 15 --json ${out}/out.json --report ${out}/report
                        --write-species ${out}/sunflower-extended.json
                OUTPUT_VARIABLE text RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "ikebana validate --paper failed (${rc}):\n${text}")
endif()
foreach(f out.json report/report.md report/model_vs_data.svg report/residual_insertion.svg sunflower-extended.json)
  if(NOT EXISTS ${out}/${f})
    message(FATAL_ERROR "validate did not write ${f}")
  endif()
endforeach()
file(READ ${out}/out.json json)
string(JSON n GET "${json}" n_trials)
string(JSON found GET "${json}" discrepancy_found)
string(JSON cause GET "${json}" causes 0 covariate)
string(JSON gain GET "${json}" extended gain)
string(JSON cv GET "${json}" baseline cv_rmse_gf)
string(JSON explanation GET "${json}" causes 0 explanation)
if(NOT n EQUAL 6 OR NOT found STREQUAL "ON" OR NOT cause STREQUAL "insertion" OR gain LESS_EQUAL 0)
  message(FATAL_ERROR "unexpected result: n_trials ${n}, found ${found}, first cause ${cause}, gain ${gain}")
endif()
if(NOT explanation MATCHES "Physical reading")
  message(FATAL_ERROR "the insertion count is a standard column and should be read physically: ${explanation}")
endif()
execute_process(COMMAND ${IKEBANA} species check ${out}/sunflower-extended.json RESULT_VARIABLE rc OUTPUT_VARIABLE text ERROR_VARIABLE text)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the extended species does not pass species check:\n${text}")
endif()
execute_process(COMMAND ${IKEBANA} predict ${DATA} --species ${out}/sunflower-extended.json -o ${out}/predicted.csv
                RESULT_VARIABLE rc OUTPUT_VARIABLE text ERROR_VARIABLE text)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "predict with the extended species failed:\n${text}")
endif()
# A species path given on the command line is taken from the working directory.
execute_process(COMMAND ${IKEBANA} predict ${DATA} --species sunflower-extended.json -o predicted_here.csv WORKING_DIRECTORY ${out}
                RESULT_VARIABLE rc OUTPUT_VARIABLE text ERROR_VARIABLE text)
if(NOT rc EQUAL 0 OR NOT EXISTS ${out}/predicted_here.csv)
  message(FATAL_ERROR "predict with a species path relative to the working directory failed:\n${text}")
endif()

# Issue 40: an extension must not break what it did not fit. Fitted to Table 2's forces and holding a
# stem too, the extended sunflower stood 16 insertions in the paper's experiment (measured 5.8, the
# baseline 6.8): validate says so, looks again with the falls as a constraint, and writes the species
# whose extension applies to the push alone, which keeps the falls. Fifteen flowers, as the paper.
execute_process(COMMAND ${IKEBANA} validate --paper --json ${out}/constrained.json --write-species ${out}/constrained-species.json
                OUTPUT_VARIABLE text RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "ikebana validate --paper failed (${rc}):\n${text}")
endif()
foreach(said "WORSE: insertions until the flower falls (the paper's experiment): extended 16 against the measured 5.8 (the baseline 6.8)"
             "Looked for again with the falls as a constraint: the extension applies to the push alone")
  string(FIND "${text}" "${said}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "validate --paper does not say '${said}':\n${text}")
  endif()
endforeach()
file(READ ${out}/constrained.json json)
string(JSON applies GET "${json}" paper_experiment extended applies_to)
string(JSON falls GET "${json}" paper_experiment extended insertions_to_fall)
string(JSON base_falls GET "${json}" paper_experiment baseline insertions_to_fall)
string(JSON others LENGTH "${json}" other_measurements)
math(EXPR last "${others} - 1")
foreach(i RANGE ${last})
  string(JSON worse GET "${json}" other_measurements ${i} worse)
  string(JSON name GET "${json}" other_measurements ${i} name)
  if(worse)
    message(FATAL_ERROR "the species written is still worse on ${name}")
  endif()
endforeach()
if(NOT applies STREQUAL "push" OR falls GREATER 7.8)
  message(FATAL_ERROR "the extension written applies to ${applies} and the flowers fall after ${falls} insertions (baseline ${base_falls})")
endif()
file(READ ${out}/constrained-species.json species)
string(JSON written GET "${species}" deterioration applies_to)
if(NOT written STREQUAL "push")
  message(FATAL_ERROR "the species file's extension applies to '${written}', not the push alone")
endif()

# Issue 57: the paper's falls are a measured outcome. What holds a stem at rest is fitted to them (a level
# on the holding alone, over 100 flowers), the species written carries it as a term with "applies_to":
# "hold", and with it the experiment's flowers fall within half an insertion of the paper's 5.8 (over the
# 100 and over the paper's 15) and break within half an insertion of its 2.6; the forces are the push's.
string(FIND "${text}" "The falls as a measured outcome: what holds a stem at rest is what the forces cannot see" at)
if(at EQUAL -1)
  message(FATAL_ERROR "validate --paper does not say how it fitted the holding to the falls:\n${text}")
endif()
string(JSON fit_falls GET "${json}" paper_experiment extended hold_fit insertions_to_fall)
string(JSON factor GET "${json}" paper_experiment extended hold_fit hold_factor)
string(JSON breaks GET "${json}" paper_experiment extended insertions_to_break)
if(fit_falls LESS 5.3 OR fit_falls GREATER 6.3 OR falls LESS 5.3 OR falls GREATER 6.3 OR breaks LESS 2.1 OR breaks GREATER 3.1)
  message(FATAL_ERROR "with the holding fitted (x${factor}) the flowers fall after ${fit_falls} (100 flowers) and ${falls} (15) insertions "
                      "and break after ${breaks}: the paper's 5.8 and 2.6 are more than half an insertion away")
endif()
string(JSON terms LENGTH "${species}" deterioration terms)
math(EXPR last_term "${terms} - 1")
string(JSON hold_term GET "${species}" deterioration terms ${last_term} applies_to)
if(NOT hold_term STREQUAL "hold")
  message(FATAL_ERROR "the species written has no term on the holding alone:\n${species}")
endif()
