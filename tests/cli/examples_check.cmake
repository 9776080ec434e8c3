# Every case file in examples/ is accepted by `softflow check` (which parses
# and validates it as a run would, without meshing): an example that a key
# rename or a new rule left behind fails here, not in a user's hands
# (a sweep file's base case is checked the same way).
file(GLOB cases ${EXAMPLES}/*.toml)
list(LENGTH cases n)
if(n LESS 5)
  message(FATAL_ERROR "found only ${n} case files in ${EXAMPLES}")
endif()
foreach(case ${cases})
  execute_process(COMMAND ${SOFTFLOW} check ${case} RESULT_VARIABLE rc OUTPUT_QUIET
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "softflow check ${case}: exit ${rc}\n${err}")
  endif()
endforeach()
message(STATUS "${n} example case files pass softflow check")
