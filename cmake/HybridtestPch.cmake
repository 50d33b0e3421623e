# Precompiled headers for the layer libraries, the hybridtest executable and the tests: the third-party
# headers that most translation units include (nlohmann/json, Eigen, yaml-cpp, fmt, the standard
# library; CLI11 for the executable) are parsed once per build instead of once per file. The
# layer libraries share one precompiled header (REUSE_FROM the first layer), the executable has
# its own (it adds CLI11). Optimisation flags are unchanged; only the parsing is shared.
#
# HYBRIDTEST_PCH: on by default, off by default when the compiler launcher is ccache (ccache 4.7
# does not cache a file compiled with a precompiled header unless its sloppiness includes
# pch_defines and time_macros; without the header, ccache's hits are worth more). Decided again
# at every configure unless given with -DHYBRIDTEST_PCH=ON|OFF.
if(NOT DEFINED HYBRIDTEST_PCH)
  if(CMAKE_CXX_COMPILER_LAUNCHER MATCHES "ccache")
    set(hybridtest_pch_default OFF)
    message(STATUS "hybridtest: precompiled headers off (ccache launcher; -DHYBRIDTEST_PCH=ON forces them)")
  else()
    set(hybridtest_pch_default ON)
  endif()
else()
  set(hybridtest_pch_default ${HYBRIDTEST_PCH})
endif()

set(HYBRIDTEST_PCH_HEADERS
  <algorithm> <array> <chrono> <cmath> <cstdint> <filesystem> <fstream> <functional> <limits>
  <map> <memory> <optional> <span> <sstream> <string> <string_view> <vector>
  <fmt/core.h> <fmt/format.h>
  <nlohmann/json.hpp>
  <yaml-cpp/yaml.h>
  <Eigen/Core> <Eigen/Cholesky> <Eigen/Eigenvalues> <Eigen/Geometry> <Eigen/LU>)

# hybridtest_pch_cxx(OUT HEADER...): the HEADERs for C++ sources only. A target may also compile C
# (the benchmarks compile SymPy's generated C); a C translation unit must not get a header of
# <algorithm> and Eigen. An angle-bracket header's closing '>' is written $<ANGLE-R> inside the
# generator expression.
function(hybridtest_pch_cxx out)
  set(result "")
  foreach(header IN LISTS ARGN)
    string(REGEX REPLACE ">$" "$<ANGLE-R>" header "${header}")
    list(APPEND result "$<$<COMPILE_LANGUAGE:CXX>:${header}>")
  endforeach()
  set(${out} "${result}" PARENT_SCOPE)
endfunction()

# hybridtest_pch_share(TARGET GROUP HEADER...): TARGET uses the precompiled header of HEADERs
# shared by the targets of GROUP (REUSE_FROM); the group's first target creates it.
function(hybridtest_pch_share target group)
  if(NOT hybridtest_pch_default)
    return()
  endif()
  get_property(owner GLOBAL PROPERTY HYBRIDTEST_PCH_OWNER_${group})
  if(NOT owner)
    hybridtest_pch_cxx(headers ${ARGN})
    target_precompile_headers(${target} PRIVATE ${headers})
    set_property(GLOBAL PROPERTY HYBRIDTEST_PCH_OWNER_${group} ${target})
  else()
    target_precompile_headers(${target} REUSE_FROM ${owner})
  endif()
endfunction()

# hybridtest_pch(TARGET): TARGET (a static layer library) uses the layers' shared header.
function(hybridtest_pch target)
  hybridtest_pch_share(${target} layers ${HYBRIDTEST_PCH_HEADERS})
endfunction()

# hybridtest_pch_app(TARGET [HEADER...]): an executable's own precompiled header (the shared
# headers and the HEADERs it adds: CLI11 for hybridtest, Google Benchmark for the benchmarks).
function(hybridtest_pch_app target)
  if(NOT hybridtest_pch_default)
    return()
  endif()
  hybridtest_pch_cxx(headers ${HYBRIDTEST_PCH_HEADERS} ${ARGN})
  target_precompile_headers(${target} PRIVATE ${headers})
endfunction()

# hybridtest_pch_tests(TARGET): the GoogleTest executables share one precompiled header (the
# shared headers, GoogleTest and GoogleMock: about 30% of a test file's compile time). Their
# compile options are the same; the definitions they add (HYBRIDTEST_SOURCE_DIR, ...) are not
# used by the header.
function(hybridtest_pch_tests target)
  hybridtest_pch_share(${target} tests ${HYBRIDTEST_PCH_HEADERS} <gtest/gtest.h> <gmock/gmock.h>)
endfunction()
