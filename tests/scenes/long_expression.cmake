# A parameter set to a chain of TERMS additions through --set (issue 29: 64 000 terms overflowed the
# stack): `0+0+...+0.3` validates, and `0+0+...-0.3` is refused for its value, so the chain was evaluated.
string(REPEAT "0+" ${TERMS} zeros)
execute_process(COMMAND ${CSIM} validate ${SCENE} --set "parameters.mu==${zeros}0.3"
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0 OR NOT out MATCHES "valid")
  message(FATAL_ERROR "mu = 0+...+0.3: exit status ${status}, expected 0\nstdout: ${out}\nstderr: ${err}")
endif()
execute_process(COMMAND ${CSIM} validate ${SCENE} --set "parameters.mu==${zeros}-0.3"
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 2 OR NOT err MATCHES "mu: must be >= 0 \\(got -0.3\\)")
  message(FATAL_ERROR "mu = 0+...-0.3: exit status ${status}, expected 2 and 'must be >= 0'\nstderr: ${err}")
endif()
