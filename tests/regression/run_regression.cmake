# Runs a case and compares its timeseries.csv with the stored reference.
# LAUNCHER (optional) prefixes the command, e.g. "mpiexec -n 2 --oversubscribe".
file(REMOVE_RECURSE ${WORK})
string(REPLACE ";" " " launcher_text "${LAUNCHER}")
separate_arguments(launcher UNIX_COMMAND "${launcher_text}")
execute_process(COMMAND ${launcher} ${SOFTFLOW} run ${CASE} -o ${WORK} -q RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "run failed (${rc}): ${err}")
endif()
execute_process(COMMAND python3 ${CMAKE_CURRENT_LIST_DIR}/compare_timeseries.py ${WORK}/timeseries.csv
                        ${REFERENCE} RESULT_VARIABLE rc OUTPUT_VARIABLE out)
message(STATUS "${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "timeseries differs from ${REFERENCE}")
endif()
