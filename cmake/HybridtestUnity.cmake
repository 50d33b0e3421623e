# Unity builds for the layer libraries and the executable: CMake compiles their sources in
# batches (one translation unit per HYBRIDTEST_UNITY_BATCH files), so the headers and the
# template instantiations that the files of a target share (Eigen, fmt, nlohmann/json,
# yaml-cpp, CLI11, the engine's templates) are compiled once per batch instead of once per
# file. On 2 cores the layer libraries took about half the compile time they take file by file;
# the executable's 24 files, 139 s of user CPU in 3 batches (104 s wall, nearly idle machine),
# where file by file they had taken about 1,000 s of compile jobs at a load of 2-4. Each
# subcommand registers itself under a name of its own (apps/hybridtest/command.h).
#
# HYBRIDTEST_UNITY: ON by default; -DHYBRIDTEST_UNITY=OFF compiles file by file (quicker to
# rebuild one file while editing it).
#
# A file that defines, in its anonymous namespace, a name that another file of its target also
# defines cannot share a batch with it: it is compiled on its own (HYBRIDTEST_UNITY_ALONE, with
# the name). Better still, rename the helper or move the shared one into a header.
option(HYBRIDTEST_UNITY "Compile the layer libraries and the executable as unity builds" ON)
set(HYBRIDTEST_UNITY_BATCH 8)
set(HYBRIDTEST_UNITY_ALONE
  src/hybridtest/campaign/summary.cc  # kNaN (case_runner.cc)
  src/hybridtest/fmi/fmu3_instance.cc  # SharedObject (fmu2_instance.cc)
  src/hybridtest/monitor/real_time_panel.cc  # Number (monitor_state.cc)
  # HttpServer::Impl has members of types from the file's anonymous namespace: in a file that
  # another includes, GCC flags that (-Wsubobject-linkage).
  src/hybridtest/monitor/http_server.cc
  src/hybridtest/symbolic/write_equations.cc  # Symbol (compiled_model.cc)
  src/hybridtest/transfer/modbus/register_map_layout.cc  # TableName (register_map.cc)
)

# hybridtest_unity(TARGET): TARGET's sources in unity batches, but those listed above.
function(hybridtest_unity target)
  if(NOT HYBRIDTEST_UNITY)
    return()
  endif()
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON
    UNITY_BUILD_BATCH_SIZE ${HYBRIDTEST_UNITY_BATCH})
  list(TRANSFORM HYBRIDTEST_UNITY_ALONE PREPEND ${PROJECT_SOURCE_DIR}/
    OUTPUT_VARIABLE alone)
  set_source_files_properties(${alone} TARGET_DIRECTORY ${target}
    PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
endfunction()
