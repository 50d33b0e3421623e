# Warnings used by every hybridtest target. Third-party headers come in as system headers
# (-isystem: Eigen, HDF5, GoogleTest, pybind11, ...), so these speak of the project's own files.
# A false positive is silenced at the narrowest scope that works, with a comment saying why.
#
# HYBRIDTEST_WERROR (OFF by default; scripts/build.sh passes $HYBRIDTEST_WERROR): every warning in
# a project file is an error, so that CI can fail on a new one.
option(HYBRIDTEST_WERROR "Treat warnings in hybridtest's own files as errors (CI)" OFF)
add_library(hybridtest_warnings INTERFACE)
target_compile_options(hybridtest_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
  -Wnon-virtual-dtor -Woverloaded-virtual -Wnull-dereference
  $<$<BOOL:${HYBRIDTEST_WERROR}>:-Werror>)
