# A small run writes the documented files, and summary.json holds the promised keys.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
file(READ ${CASE} text)
string(REPLACE "fields = false" "fields = true" text "${text}")
file(WRITE ${WORK}/case.toml "${text}")
execute_process(COMMAND ${SOFTFLOW} run ${WORK}/case.toml -o ${WORK}/out -q RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "run failed (${rc}): ${err}")
endif()
foreach(f case.toml summary.json fields.pvd matrix.vtu object_1.vtu)
  if(NOT EXISTS ${WORK}/out/${f})
    message(FATAL_ERROR "missing ${f}")
  endif()
endforeach()
# Without -q the static solve prints each interface's pressure jump (README).
execute_process(COMMAND ${SOFTFLOW} run ${WORK}/case.toml -o ${WORK}/out_loud --overwrite
                RESULT_VARIABLE rc OUTPUT_VARIABLE printed ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT printed MATCHES "object 1: pressure jump [0-9.]+ \\(Laplace 2 Gamma / R = ")
  message(FATAL_ERROR "the static solve does not print the pressure jump (${rc}):\n${printed}${err}")
endif()
# A PETSc option nothing reads (misspelt) is named in a warning, not ignored.
execute_process(COMMAND ${SOFTFLOW} run ${WORK}/case.toml -o ${WORK}/out_typo -q -- -stokes_ksp_typo gmres
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT err MATCHES "warning: PETSc never read these options \\(misspelt\\?\\): -stokes_ksp_typo")
  message(FATAL_ERROR "an unused PETSc option went unreported (${rc}): ${err}")
endif()
file(READ ${WORK}/out/summary.json summary)
foreach(key unknowns velocity pressure solve_seconds assembly_seconds iterations
            dimensionless_groups pressure_jump volume area centre min_quality interface_nodes
            equator_nodes equator_nodes_requested)
  string(FIND "${summary}" "\"${key}\"" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "summary.json lacks '${key}'")
  endif()
endforeach()
# The resolved case reproduces the run.
execute_process(COMMAND ${SOFTFLOW} check ${WORK}/out/case.toml RESULT_VARIABLE rc OUTPUT_VARIABLE resolved)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the resolved case.toml does not validate")
endif()
# ParaView can read what was written (structure and sizes checked without ParaView).
execute_process(COMMAND python3 ${CMAKE_CURRENT_LIST_DIR}/check_vtu.py ${WORK}/out RESULT_VARIABLE rc
                OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "fields are malformed: ${out}${err}")
endif()
message(STATUS "${out}")
