# HYBRIDTEST_PYTHON_PACKAGE: build the Python package `hybridtest` (python/) with pybind11. Unless
# given with -DHYBRIDTEST_PYTHON_PACKAGE=ON|OFF, it is decided again at every configure: ON when
# pybind11 (Debian: pybind11-dev) and the Python 3 development files (python3-dev) are found,
# OFF otherwise with a message, so that a tree first configured without them (scripts/build.sh
# --app) gets the package once scripts/install-deps.sh has installed them.
#
# The interpreter is the `python3` first on PATH when the tree is first configured (a pyenv or
# virtual environment's as well as Debian's /usr/bin/python3), resolved to the executable behind
# it (a pyenv shim runs another program); -DPython3_EXECUTABLE=... builds for another one. The
# package records it (hybridtest/_build_info.py) and names it when another interpreter imports it.
if(NOT DEFINED Python3_EXECUTABLE)
  find_program(hybridtest_python3_on_path NAMES python3 NO_CACHE)
  if(hybridtest_python3_on_path)
    execute_process(COMMAND ${hybridtest_python3_on_path} -c "import sys; print(sys.executable)"
      OUTPUT_VARIABLE hybridtest_python3_real OUTPUT_STRIP_TRAILING_WHITESPACE
      RESULT_VARIABLE hybridtest_python3_status ERROR_QUIET)
    if(hybridtest_python3_status EQUAL 0 AND EXISTS "${hybridtest_python3_real}")
      set(Python3_EXECUTABLE ${hybridtest_python3_real} CACHE FILEPATH
        "Python 3 interpreter of the package (default: the python3 first on PATH)")
    endif()
  endif()
endif()
if(NOT DEFINED HYBRIDTEST_PYTHON_PACKAGE OR HYBRIDTEST_PYTHON_PACKAGE)
  find_package(Python3 COMPONENTS Interpreter Development.Module QUIET)
  if(Python3_FOUND)
    find_package(pybind11 CONFIG QUIET)
  endif()
endif()
if(NOT DEFINED HYBRIDTEST_PYTHON_PACKAGE)
  if(Python3_FOUND AND pybind11_FOUND)
    set(HYBRIDTEST_PYTHON_PACKAGE ON)
  else()
    set(HYBRIDTEST_PYTHON_PACKAGE OFF)
    message(STATUS "hybridtest: Python package off (pybind11-dev or python3-dev not found; "
      "scripts/install-deps.sh installs them)")
  endif()
elseif(HYBRIDTEST_PYTHON_PACKAGE AND NOT (Python3_FOUND AND pybind11_FOUND))
  message(FATAL_ERROR "HYBRIDTEST_PYTHON_PACKAGE=ON needs pybind11 (Debian: pybind11-dev) and the "
    "Python 3 development files (python3-dev): install them with scripts/install-deps.sh")
endif()
if(HYBRIDTEST_PYTHON_PACKAGE)
  # The module links the layer libraries into a shared object.
  set(CMAKE_POSITION_INDEPENDENT_CODE ON)
endif()
