# `cmake --install BUILD --prefix P` installs hybridtest as a C++ package:
#   P/include/hybridtest/<layer>/*.h    the headers (and the generated common/version.h)
#   P/lib/libhybridtest_<layer>.a       one static library per layer
#   P/lib/cmake/hybridtest/             hybridtestConfig.cmake, its version file, the targets
#   P/bin/hybridtest                    the command line
#   P/lib/hybridtest/                   the modules it loads or ships, hybridtest_fmu.so and
#                                       hybridtest_hdf5.so (installed by apps/*/CMakeLists.txt)
# A consumer writes `find_package(hybridtest CONFIG REQUIRED)` and links `hybridtest::hybridtest`
# (every layer); each layer is also exported as `hybridtest::<layer>` (hybridtest::multibody...).
# Every library that src/hybridtest/CMakeLists.txt makes is installed, so a new layer needs no
# edit here; its third-party dependencies must be found in cmake/hybridtestConfig.cmake.in too.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(HYBRIDTEST_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/hybridtest)

# The layer libraries: every library target of src/hybridtest/ except the warnings.
get_property(hybridtest_dir_targets DIRECTORY ${PROJECT_SOURCE_DIR}/src/hybridtest
  PROPERTY BUILDSYSTEM_TARGETS)
set(HYBRIDTEST_LAYER_TARGETS "")
foreach(target IN LISTS hybridtest_dir_targets)
  get_target_property(type ${target} TYPE)
  if(target STREQUAL "hybridtest_warnings" OR NOT type MATCHES "^(STATIC|INTERFACE)_LIBRARY$")
    continue()
  endif()
  string(REGEX REPLACE "^hybridtest_" "" layer ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${layer})
  add_library(hybridtest::${layer} ALIAS ${target})
  list(APPEND HYBRIDTEST_LAYER_TARGETS ${target})
endforeach()

# hybridtest::hybridtest: the whole library, C++20. (The name `hybridtest` is the CLI's.)
add_library(hybridtest_library INTERFACE)
set_target_properties(hybridtest_library PROPERTIES EXPORT_NAME hybridtest)
target_link_libraries(hybridtest_library INTERFACE ${HYBRIDTEST_LAYER_TARGETS})
target_compile_features(hybridtest_library INTERFACE cxx_std_20)
add_library(hybridtest::hybridtest ALIAS hybridtest_library)

install(TARGETS ${HYBRIDTEST_LAYER_TARGETS} hybridtest_library EXPORT hybridtestTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/src/hybridtest/
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/hybridtest
  FILES_MATCHING PATTERN "*.h")
install(DIRECTORY ${PROJECT_BINARY_DIR}/src/hybridtest/generated/hybridtest/
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/hybridtest
  FILES_MATCHING PATTERN "*.h")
install(EXPORT hybridtestTargets NAMESPACE hybridtest:: DESTINATION ${HYBRIDTEST_INSTALL_CMAKEDIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/hybridtestConfig.cmake.in
  ${PROJECT_BINARY_DIR}/hybridtestConfig.cmake
  INSTALL_DESTINATION ${HYBRIDTEST_INSTALL_CMAKEDIR})
# 0.x: a minor version may change the API, so only the same major.minor is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/hybridtestConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/hybridtestConfig.cmake
  ${PROJECT_BINARY_DIR}/hybridtestConfigVersion.cmake
  DESTINATION ${HYBRIDTEST_INSTALL_CMAKEDIR})

# The command line, with the SymPy reader that check-model runs from beside the binary.
install(TARGETS hybridtest RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES ${PROJECT_BINARY_DIR}/apps/hybridtest/hybridtest_check_model_sympy.py
  ${PROJECT_BINARY_DIR}/apps/hybridtest/hybridtest_check_constraints_sympy.py
  DESTINATION ${CMAKE_INSTALL_BINDIR})
