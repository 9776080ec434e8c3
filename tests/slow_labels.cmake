# Read by ctest after the discovered gtest tests (see tests/CMakeLists.txt):
# a test whose suite name ends in "Slow" gets the label slow besides its
# executable's label, so that `ctest -LE slow` leaves it out.
# SOFTFLOW_GTEST_EXECUTABLES: "executable=label" pairs; gtest_discover_tests
# lists each executable's tests in <executable>_TESTS.
foreach(pair IN LISTS SOFTFLOW_GTEST_EXECUTABLES)
  string(REPLACE "=" ";" pair "${pair}")
  list(GET pair 0 executable)
  list(GET pair 1 label)
  foreach(test IN LISTS ${executable}_TESTS)
    # Suite.Test, or Prefix/Suite.Test/Param for parameterised tests.
    if(test MATCHES "(^|/)[A-Za-z0-9_]*Slow\\.")
      set_tests_properties("${test}" PROPERTIES LABELS "${label};slow")
    endif()
  endforeach()
endforeach()
