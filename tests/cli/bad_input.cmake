# Bad input gets one clear message, a non-zero exit and no output directory.
# Each case: file content, expected exit code, a substring of the message.
set(cases
  "unknown_key|[mesh]\nequator_node = 40\n|1|did you mean 'mesh.equator_nodes'"
  "wrong_type|[cell]\nheight = \"tall\"\n|1|cell.height"
  "out_of_range|[[objects]]\nradius = -1\n|1|objects[1].radius = -1"
  "overlap|[[objects]]\n[[objects]]\ncentre = [1.0, 0.0, 0.0]\n|1|overlap.toml: objects[2]"
  "crosses_wall|[[objects]]\ncentre = [0.0, 14.5, 0.0]\n|1|crosses the wall"
  "crosses_periodic_face|[[objects]]\ncentre = [14.6, 0.0, 0.0]\n|1|objects[1]"
  "syntax|equator_nodes = = 4\n|1|syntax"
  "overflow|[cell]\nlength = 1e400\n|1|cell.length = 1e400"
  "integer_overflow|[mesh]\nequator_nodes = 9223372036854775808\n|1|mesh.equator_nodes = 9223372036854775808"
  "step_beyond_end|[time]\nstep = 2.0\nend = 1.0\n|1|time.step = 2.0"
  "control_character|[output]\ndirectory = \"out\\u0007x\"\n|1|control character"
  "particle_with_tension|[[objects]]\nmodel = \"neo_hookean\"\nmodulus = 1.0\ncapillary_number = 0.1\n|1|objects[1].capillary_number = 0.1: only for model"
  "petsc_value|[solver]\npetsc_options = \"-stokes_ksp_type nonsense\"\n|1|PETSc rejected them: Unable to find requested KSP type nonsense"
  "model_parameter_missing|[matrix]\nmodel = \"oldroyd_b\"\nsolvent_viscosity = 0.5\nmodulus = 1.0\n|1|matrix.relaxation_time: missing")
# Issue 33, items 5-7 and 12: each passed `check`, then the run failed late,
# never ended, or ignored what was asked.
string(REPEAT "n" 250 long_name)
list(APPEND cases
  "long_name|[case]\nname = \"${long_name}\"\n|1|of 250 bytes: at most 239 are allowed"
  "blank_name|[case]\nname = \"   \"\n|1|case.name = \"   \": must contain a character other than spaces"
  "petsc_word|[solver]\npetsc_options = \"-stokes_ksp_type gmres ksp_monitor\"\n|1|the word 'ksp_monitor' (word 3)"
  "thin_ellipsoid|[[objects]]\nshape = \"ellipsoid\"\nsemi_axes = [1e-3, 1.0, 1.0]\n|1|semi-axis ratio a_max / a_min = 1000"
  "huge_angle|[[objects]]\nshape = \"ellipsoid\"\nsemi_axes = [1.2, 1.0, 1.0]\nrotation_deg = [1e300, 0.0, 0.0]\n|1|objects[1].rotation_deg[1] = 1e+300: must be in [-360, 360]"
  "short_relaxation|[matrix]\nmodel = \"oldroyd_b\"\nsolvent_viscosity = 0.5\npolymer_viscosity = 0.5\nrelaxation_time = 1e-300\n[time]\nstep = 0.05\nend = 1.0\n|1|matrix.relaxation_time = 1e-300"
  "fast_oscillation|[flow]\ntype = \"oscillatory\"\nstrain_amplitude = 0.5\nfrequency = 1000.0\n[time]\nstep = 0.05\nend = 1.0\n|1|steps per period")
# Arrays nested 10000 deep (toml11 recursion): refused, not a crash.
string(REPEAT "[" 10000 open)
string(REPEAT "]" 10000 close)
list(APPEND cases "deep_nesting|a = ${open}${close}\n|1|at most 64")
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
foreach(entry ${cases})
  string(REPLACE "|" ";" parts "${entry}")
  list(GET parts 0 name)
  list(GET parts 1 content)
  list(GET parts 2 expected_rc)
  list(GET parts 3 expected_text)
  string(REPLACE "\\n" "\n" content "${content}")
  file(WRITE ${WORK}/${name}.toml "${content}")
  execute_process(COMMAND ${SOFTFLOW} run ${name}.toml -o out_${name} WORKING_DIRECTORY ${WORK}
                  RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_VARIABLE out)
  if(NOT rc EQUAL expected_rc)
    message(FATAL_ERROR "${name}: exit code ${rc}, expected ${expected_rc}\n${err}")
  endif()
  string(FIND "${err}" "${expected_text}" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "${name}: message lacks '${expected_text}':\n${err}")
  endif()
  file(GLOB leftovers ${WORK}/out_${name}*)
  if(leftovers)
    message(FATAL_ERROR "${name}: output left behind: ${leftovers}")
  endif()
  message(STATUS "${name}: exit ${rc}: ${err}")
endforeach()

# Command-line mistakes (issue 11, item 7): one message naming what is wrong,
# exit 1, nothing run. Each: name|arguments (^-separated)|a substring of the message.
file(WRITE ${WORK}/good.toml "[[objects]]\n[mesh]\nequator_nodes = 16\nfar_size = 2.0\n")
# Sweeps (issue 33, items 8-9): checked like single cases, no value twice.
file(WRITE ${WORK}/duplicate_sweep.toml "[[objects]]\ncapillary_number = [0.1, 0.2, 0.1]\n")
file(WRITE ${WORK}/nameless_sweep.toml "[case]\nname = \"\"\n[[objects]]\ncapillary_number = [0.1, 0.2]\n")
set(command_cases
  "unknown_subcommand|frobnicate|unknown subcommand 'frobnicate' (allowed: run,"
  "zero_jobs|sweep^good.toml^--jobs^0|--jobs = 0: a whole number of cases at a time, at least 1"
  "empty_output|run^good.toml^-o^|-o/--output is empty"
  "petsc_word_after_dashes|run^good.toml^-o^out_dashes^--^stokes_ksp_monitor|the word 'stokes_ksp_monitor' (word 1)"
  "duplicate_sweep_value|check^duplicate_sweep.toml|objects[1].capillary_number = [0.1, 0.2, 0.1]: lists 0.1 twice"
  "duplicate_sweep_value_run|sweep^duplicate_sweep.toml|lists 0.1 twice"
  "nameless_sweep|sweep^nameless_sweep.toml|case.name = \"\": must be a non-empty name")
string(REPEAT "o" 250 long_output)
list(APPEND command_cases "long_output|run^good.toml^-o^${long_output}|of 250 bytes: at most 239")
foreach(entry ${command_cases})
  string(REPLACE "|" ";" parts "${entry}")
  list(GET parts 0 name)
  list(GET parts 1 argument_text)
  list(GET parts 2 expected_text)
  # A trailing "^" stands for an empty last argument (-o ""), which an
  # unquoted list expansion would drop.
  set(empty_last FALSE)
  if(argument_text MATCHES "\\^$")
    set(empty_last TRUE)
    string(REGEX REPLACE "\\^$" "" argument_text "${argument_text}")
  endif()
  string(REPLACE "^" ";" arguments "${argument_text}")
  if(empty_last)
    execute_process(COMMAND ${SOFTFLOW} ${arguments} "" WORKING_DIRECTORY ${WORK}
                    RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_VARIABLE out)
  else()
    execute_process(COMMAND ${SOFTFLOW} ${arguments} WORKING_DIRECTORY ${WORK}
                    RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_VARIABLE out)
  endif()
  if(NOT rc EQUAL 1)
    message(FATAL_ERROR "${name}: exit code ${rc}, expected 1\n${err}${out}")
  endif()
  string(FIND "${err}" "${expected_text}" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "${name}: message lacks '${expected_text}':\n${err}")
  endif()
  string(LENGTH "${err}" length)
  if(length GREATER 300)
    message(FATAL_ERROR "${name}: a message of ${length} characters:\n${err}")
  endif()
  message(STATUS "${name}: exit ${rc}: ${err}")
endforeach()
if(EXISTS ${WORK}/output)
  message(FATAL_ERROR "a refused command wrote ${WORK}/output")
endif()
