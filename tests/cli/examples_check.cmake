# Every case file in examples/ is accepted by `softflow check` (which parses
# and validates it as a run would, without meshing): an example that a key
# rename or a new rule left behind fails here, not in a user's hands
# (a sweep file's base case is checked the same way).
file(GLOB cases ${EXAMPLES}/*.toml)
list(LENGTH cases n)
if(n LESS 5)
  message(FATAL_ERROR "found only ${n} case files in ${EXAMPLES}")
endif()
# One process for all (`softflow check A B ...`): one "FILE: valid" line each.
execute_process(COMMAND ${SOFTFLOW} check ${cases} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "softflow check of the examples: exit ${rc}\n${err}")
endif()
foreach(case ${cases})
  string(FIND "${out}" "${case}: valid" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "softflow check: no verdict for ${case}:\n${out}\n${err}")
  endif()
endforeach()
message(STATUS "${n} example case files pass softflow check")
