# Fails when a folder includes a header of a layer above it, or when components/ pulls in an API
# that plain data must not know (Vulkan, GLFW, hidapi).
set(rules
  "engine|components/|systems/|game/"
  "components|systems/|game/|vulkan/|GLFW/|hidapi"
  "systems|game/")
set(failures "")
foreach(rule IN LISTS rules)
  string(REPLACE "|" ";" parts "${rule}")
  list(POP_FRONT parts folder)
  file(GLOB_RECURSE sources "${ROOT}/${folder}/*.hpp" "${ROOT}/${folder}/*.cpp" "${ROOT}/${folder}/*.h")
  foreach(source IN LISTS sources)
    file(STRINGS "${source}" includes REGEX "^[ \t]*#[ \t]*include")
    foreach(line IN LISTS includes)
      foreach(forbidden IN LISTS parts)
        string(FIND "${line}" "${forbidden}" at)
        if(NOT at EQUAL -1)
          string(APPEND failures "\n  ${source}: ${line} (${folder}/ must not include ${forbidden})")
        endif()
      endforeach()
    endforeach()
  endforeach()
endforeach()
if(failures)
  message(FATAL_ERROR "layering violated:${failures}")
endif()
message(STATUS "layering: engine <- components <- systems <- game holds")
