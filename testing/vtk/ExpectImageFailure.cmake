# Runs one image test against a deliberately wrong baseline and succeeds only if the test fails on the image
# comparison: non-zero exit status AND vtkTesting's "Failed Image Test" message (a crash or a missing baseline
# does not count).
execute_process(COMMAND "${DRIVER}" "${TEST}" -T "${TEMP}" -V "${BASELINE}"
  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(status EQUAL 0)
  message(FATAL_ERROR "${TEST} passed against the wrong baseline ${BASELINE}")
endif()
if(NOT "${out}${err}" MATCHES "Failed Image Test")
  message(FATAL_ERROR "${TEST} failed without an image comparison failure (status ${status}):\n${out}\n${err}")
endif()
string(REGEX MATCH "Failed Image Test[^\n]*" line "${out}${err}")
message(STATUS "as expected: ${line}")
