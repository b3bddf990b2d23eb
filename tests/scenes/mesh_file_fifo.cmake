# A mesh `file:` that is a FIFO is refused before it is opened: opening a FIFO for reading blocks until a
# writer comes, so csim hung (issue 29). The FIFO and its scene are made in WORK; the test has a TIMEOUT.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND mkfifo ${WORK}/mesh.msh RESULT_VARIABLE made)
if(NOT made EQUAL 0)
  message(FATAL_ERROR "mkfifo ${WORK}/mesh.msh failed")
endif()
file(WRITE ${WORK}/scene.yaml "dimension: 2
bodies:
  plate:
    type: elastic
    mesh: {file: mesh.msh}
    material: {young: 1e6, poisson: 0.3, density: 1000}
time: {end: 1e-2, step: 1e-3}
")
execute_process(COMMAND ${CSIM} validate ${WORK}/scene.yaml RESULT_VARIABLE status ERROR_VARIABLE err TIMEOUT 20)
if(NOT status EQUAL 2 OR NOT err MATCHES "scene.yaml:5: bodies.plate.mesh.file: '.*mesh.msh' is a FIFO \\(named pipe\\), not a regular file")
  message(FATAL_ERROR "exit status ${status}, expected 2 and the FIFO named at bodies.plate.mesh.file\nstderr: ${err}")
endif()
