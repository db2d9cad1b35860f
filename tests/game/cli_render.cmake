# `ikebana render` end to end on the default scene: three PNGs per frame, every stereo mode, and the
# validation layer reporting no error (the command exits 4 when it does).
foreach(mode sbs rows anaglyph mono)
  set(out ${WORK}/render_${mode})
  file(REMOVE_RECURSE ${out})
  execute_process(COMMAND ${IKEBANA} render --out ${out} --frames 2 --width 160 --height 90 --stereo ${mode} --validation
                  OUTPUT_VARIABLE text ERROR_VARIABLE err RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "ikebana render --stereo ${mode} failed (${rc}):\n${text}\n${err}")
  endif()
  if(NOT text MATCHES "validation: 0 errors")
    message(FATAL_ERROR "no clean validation report for ${mode}:\n${text}")
  endif()
  foreach(f frame_0001_left frame_0001_right frame_0001_composed frame_0002_composed)
    if(NOT EXISTS ${out}/${f}.png)
      message(FATAL_ERROR "render --stereo ${mode} did not write ${f}.png")
    endif()
  endforeach()
endforeach()
