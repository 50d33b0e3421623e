# The out-of-tree consumer, run by CTest with `cmake -P`: installs the current build into a
# fresh prefix (a copy, no rebuild), configures and builds examples/cpp/01_step_a_session and
# 02_run_spec_in_code against it with find_package(hybridtest), then runs them against the
# installed CLI: 01 on the rotor's dummy test (compare_final_state.py), 02 against the
# two-actuator blade of examples/06 (compare_journals.py); and `hybridtest export-fmu` with the
# installed FMU binary, and `hybridtest export --hdf5` with the installed HDF5 writer.
# -D inputs: BUILD_DIR, SOURCE_DIR, WORK_DIR, GENERATOR, CXX_COMPILER, CXX_LAUNCHER,
#            CXX_FLAGS, BUILD_TYPE, PYTHON.
function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT status EQUAL 0)
    string(REPLACE ";" " " command "${ARGV}")
    message(FATAL_ERROR "consumer.cmake: `${command}` failed (${status}):\n${out}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK_DIR}/prefix)
set(build ${WORK_DIR}/build)
file(REMOVE_RECURSE ${WORK_DIR})

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/cpp/01_step_a_session -B ${build}
  -G ${GENERATOR} -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=${BUILD_TYPE}
  -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_CXX_COMPILER_LAUNCHER=${CXX_LAUNCHER}
  "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}")
run(${CMAKE_COMMAND} --build ${build})
run(${PYTHON} ${CMAKE_CURRENT_LIST_DIR}/compare_final_state.py ${build}/step_a_session
  ${prefix}/bin/hybridtest ${SOURCE_DIR}/examples/rotor/dummy.yaml ${WORK_DIR}/run)
message("${run_output}")
set(build02 ${WORK_DIR}/build02)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/cpp/02_run_spec_in_code -B ${build02}
  -G ${GENERATOR} -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=${BUILD_TYPE}
  -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_CXX_COMPILER_LAUNCHER=${CXX_LAUNCHER}
  "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}")
run(${CMAKE_COMMAND} --build ${build02})
run(${PYTHON} ${CMAKE_CURRENT_LIST_DIR}/compare_journals.py ${build02}/run_spec_in_code
  ${prefix}/bin/hybridtest ${SOURCE_DIR}/examples/06_blade_two_actuators/emulated.yaml
  ${WORK_DIR}/run02)
message("${run_output}")
# The installed command line finds the installed FMU binary (<prefix>/<libdir>/hybridtest/
# hybridtest_fmu.so) for export-fmu, with nothing of the build tree on its way.
run(${prefix}/bin/hybridtest export-fmu ${SOURCE_DIR}/examples/rotor/dummy.yaml
  --out ${WORK_DIR}/rotor.fmu)
message("${run_output}")
if(NOT EXISTS ${WORK_DIR}/rotor.fmu)
  message(FATAL_ERROR "consumer.cmake: the installed export-fmu wrote no ${WORK_DIR}/rotor.fmu")
endif()
# The installed command line finds the installed HDF5 writer (<prefix>/<libdir>/hybridtest/
# hybridtest_hdf5.so), which it loads for an HDF5 export only.
file(WRITE ${WORK_DIR}/tiny.csv "t,q1\n0,1\n0.001,2\n")
run(${prefix}/bin/hybridtest export ${WORK_DIR}/tiny.csv --hdf5 ${WORK_DIR}/tiny.h5)
message("${run_output}")
if(NOT EXISTS ${WORK_DIR}/tiny.h5)
  message(FATAL_ERROR "consumer.cmake: the installed export --hdf5 wrote no ${WORK_DIR}/tiny.h5")
endif()
