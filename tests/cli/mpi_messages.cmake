# Under mpirun a command-line mistake is reported once, not once per rank.
string(REPLACE ";" " " flags_text "${MPIEXEC_FLAGS}")
separate_arguments(flags UNIX_COMMAND "${flags_text}")
execute_process(COMMAND ${MPIEXEC} -n 2 ${flags} ${SOFTFLOW} frobnicate
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(REGEX MATCHALL "unknown subcommand 'frobnicate'" hits "${out}${err}")
list(LENGTH hits n)
if(rc EQUAL 0 OR NOT n EQUAL 1)
  message(FATAL_ERROR "2 ranks: exit ${rc}, the message printed ${n} times:\n${out}${err}")
endif()
message(STATUS "2 ranks, one message: ${err}")
