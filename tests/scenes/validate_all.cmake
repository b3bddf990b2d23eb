# Runs `csim validate` on every scenes/*/scene.yaml; fails on the first that does not validate or declares
# no check.
file(GLOB scene_files ${SCENES}/*/scene.yaml)
list(LENGTH scene_files count)
if(count EQUAL 0)
  message(FATAL_ERROR "no scenes found under ${SCENES}")
endif()
foreach(scene ${scene_files})
  execute_process(COMMAND ${CSIM} validate ${scene} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${scene} does not validate: ${err}")
  endif()
  # A scene of scenes/ is a regression case: without checks `csim run` would end it with exit 0 as a
  # plain simulation, and its test would judge nothing.
  if(NOT out MATCHES ", [1-9][0-9]* checks?\\)")
    message(FATAL_ERROR "${scene} declares no check (a regression scene must be judged): ${out}")
  endif()
  message(STATUS "${out}")
endforeach()
