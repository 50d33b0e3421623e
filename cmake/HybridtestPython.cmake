# HYBRIDTEST_PYTHON: build the Python package `hybridtest` (python/) with pybind11. The default
# is ON when pybind11 (Debian: pybind11-dev) and the Python 3 development files (python3-dev)
# are found, OFF otherwise with a message. The interpreter is Debian's /usr/bin/python3 when
# it exists (the one scripts/install-deps.sh installs numpy and pytest for); give
# -DPython3_EXECUTABLE=... to build for another one.
if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python 3 interpreter of the package")
endif()
find_package(Python3 COMPONENTS Interpreter Development.Module QUIET)
if(Python3_FOUND)
  find_package(pybind11 CONFIG QUIET)
endif()
if(Python3_FOUND AND pybind11_FOUND)
  option(HYBRIDTEST_PYTHON "Build the Python package hybridtest (pybind11)" ON)
else()
  option(HYBRIDTEST_PYTHON "Build the Python package hybridtest (pybind11)" OFF)
  if(HYBRIDTEST_PYTHON)
    message(FATAL_ERROR "HYBRIDTEST_PYTHON=ON needs pybind11 (Debian: pybind11-dev) and the "
      "Python 3 development files (python3-dev): install them with scripts/install-deps.sh")
  endif()
  message(STATUS "hybridtest: Python package off (pybind11-dev or python3-dev not found; "
    "scripts/install-deps.sh installs them)")
endif()
if(HYBRIDTEST_PYTHON)
  set(CMAKE_POSITION_INDEPENDENT_CODE ON)
endif()
