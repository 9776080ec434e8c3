# Runs one case serially and on 2 MPI ranks, for the direct and the
# iterative solver (or the SOLVERS given), and compares the summaries.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
if(NOT DEFINED SOLVERS)
  set(SOLVERS direct iterative)
endif()
foreach(solver ${SOLVERS})
  file(READ ${CASE} text)
  string(APPEND text "\n[solver]\ntype = \"${solver}\"\nrtol = 1e-10\n")
  file(WRITE ${WORK}/${solver}.toml "${text}")
  execute_process(COMMAND ${SOFTFLOW} run ${WORK}/${solver}.toml -o ${WORK}/${solver}_serial -q
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "serial ${solver} run failed (${rc})")
  endif()
  string(REPLACE ";" " " flags_text "${MPIEXEC_FLAGS}")
  separate_arguments(flags UNIX_COMMAND "${flags_text}")
  execute_process(COMMAND ${MPIEXEC} -n 2 ${flags} ${SOFTFLOW} run ${WORK}/${solver}.toml
                          -o ${WORK}/${solver}_mpi2 -q
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "2-rank ${solver} run failed (${rc})")
  endif()
  execute_process(COMMAND python3 ${COMPARE} ${WORK}/${solver}_serial/summary.json
                          ${WORK}/${solver}_mpi2/summary.json RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "serial and 2-rank ${solver} solutions differ")
  endif()
endforeach()
