# Negative control: runs one image test with the testing-only shading perturbation on
# (WHITTED_TEST_PERTURB_SHADING: vtkWhittedPass::ShadingErrorForTesting 10, 1% of the traced pixels off
# by 10/255) and succeeds only if the test fails on its direct baseline pixel check: non-zero exit
# status AND the message "Baseline pixel check failed" (a crash or a missing baseline does not count).
# COMMAND: the test's command line, a ;-separated list. ALSO: a regular expression the output must match too.
set(ENV{WHITTED_TEST_PERTURB_SHADING} 1)
execute_process(COMMAND ${COMMAND} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(status EQUAL 0)
  message(FATAL_ERROR "the test passed with its shading perturbed:\n${out}\n${err}")
endif()
if(NOT "${out}${err}" MATCHES "Baseline pixel check failed")
  message(FATAL_ERROR "the test failed without a baseline pixel check failure (status ${status}):\n${out}\n${err}")
endif()
# ALSO (optional): a second check that must have failed as well, e.g. the test's independent oracle
if(DEFINED ALSO AND NOT "${out}${err}" MATCHES "${ALSO}")
  message(FATAL_ERROR "the test failed, but not on '${ALSO}' (status ${status}):\n${out}\n${err}")
endif()
string(REGEX MATCH "\\[baseline\\][^\n]*" line "${out}${err}")
message(STATUS "as expected: ${line}")
