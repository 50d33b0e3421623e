# Warnings used by every hybridtest target.
add_library(hybridtest_warnings INTERFACE)
target_compile_options(hybridtest_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
  -Wnon-virtual-dtor -Woverloaded-virtual -Wnull-dereference)
