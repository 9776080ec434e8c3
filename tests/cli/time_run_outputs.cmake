# A short run in time writes the time series, a ParaView time series, the
# summary and the plot; a mesh too poor for time.min_quality is refused
# before the run.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
file(READ ${CASE} text)
string(REPLACE "fields = false" "fields = true" text "${text}")
string(REPLACE "end = 1.0" "end = 0.5\nfields_interval = 5" text "${text}")
file(WRITE ${WORK}/case.toml "${text}")
execute_process(COMMAND ${SOFTFLOW} run ${WORK}/case.toml -o ${WORK}/out RESULT_VARIABLE rc
                OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "run failed (${rc}): ${err}")
endif()
# The ETA leaves out the first step's one-off costs (the LU factorisation):
# unknown ("--") after step 1, then estimated from the later steps.
foreach(pattern "step +10/10" "step +1/10 [^\n]*ETA --\n" "step +2/10 [^\n]*ETA [0-9]+s\n")
  if(NOT out MATCHES "${pattern}")
    message(FATAL_ERROR "progress output lacks '${pattern}':\n${out}")
  endif()
endforeach()
foreach(f case.toml summary.json timeseries.csv fields.pvd deformation.png
          fields/matrix_000005.vtu fields/object_1_000010.vtu)
  if(NOT EXISTS ${WORK}/out/${f})
    message(FATAL_ERROR "missing ${f}")
  endif()
endforeach()
# The run reports its peak memory (largest rank, all ranks) in megabytes.
file(READ ${WORK}/out/summary.json summary)
if(NOT summary MATCHES "\"peak_memory_mb\": {[^}]*\"all_ranks\": [1-9][0-9]*\\.[^}]*\"largest_rank\": [1-9]")
  message(FATAL_ERROR "summary.json lacks a positive peak_memory_mb: ${summary}")
endif()
file(STRINGS ${WORK}/out/timeseries.csv lines)
list(GET lines 0 header)
foreach(column t D theta_deg L B W xc yc zc uc vc wc volume area ellipsoid_dev min_quality)
  if(NOT "${header}," MATCHES "(^|,)${column},")
    message(FATAL_ERROR "timeseries.csv lacks column ${column}: ${header}")
  endif()
endforeach()
# The undeformed sphere at t = 0 has no orientation: theta_deg is nan there,
# a number at every later step.
list(GET lines 1 first_row)
list(GET lines 2 second_row)
if(NOT header MATCHES "^step,t,object,D,theta_deg," OR NOT first_row MATCHES "^0,0,1,[^,]*,nan,"
   OR second_row MATCHES "^[^,]*,[^,]*,[^,]*,[^,]*,nan,")
  message(FATAL_ERROR "theta_deg must be nan for the sphere at t = 0 only:\n${first_row}\n${second_row}")
endif()
list(LENGTH lines n_lines)
if(NOT n_lines EQUAL 12)  # header, t = 0, 10 steps
  message(FATAL_ERROR "timeseries.csv has ${n_lines} lines, expected 12")
endif()
execute_process(COMMAND python3 ${CMAKE_CURRENT_LIST_DIR}/check_vtu.py ${WORK}/out RESULT_VARIABLE rc
                OUTPUT_VARIABLE vtu_out ERROR_VARIABLE vtu_err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "fields are malformed: ${vtu_out}${vtu_err}")
endif()

# A quality threshold no mesh meets: refused before the time loop (exit 2),
# saying so and which mesh keys to change, with nothing written. (A mesh
# that degrades during a run is tests/cli/failures.py's "collapse".)
string(REPLACE "fields_interval = 5" "fields_interval = 5\nmin_quality = 0.9" text "${text}")
file(WRITE ${WORK}/strict.toml "${text}")
execute_process(COMMAND ${SOFTFLOW} run ${WORK}/strict.toml -o ${WORK}/strict -q RESULT_VARIABLE rc
                ERROR_VARIABLE err)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "a mesh below time.min_quality: exit ${rc}, expected 2: ${err}")
endif()
if(NOT err MATCHES "initial mesh" OR NOT err MATCHES "mesh.equator_nodes")
  message(FATAL_ERROR "the failure does not say what happened: ${err}")
endif()
if(EXISTS ${WORK}/strict)
  message(FATAL_ERROR "the refused run wrote ${WORK}/strict")
endif()
message(STATUS "refused run: ${err}")
