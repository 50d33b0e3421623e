#pragma once
// hybridtest as a C++ library: one include for the public API.
//
//   find_package(hybridtest CONFIG REQUIRED)
//   target_link_libraries(my_app PRIVATE hybridtest::hybridtest)
//
//   #include <hybridtest/hybridtest.h>
//
// examples/cpp/ shows it at work. Every header stays includable on its own
// (<hybridtest/<layer>/<name>.h>) for a program that needs one layer only.
#include "hybridtest/common/error.h"
#include "hybridtest/common/units.h"
#include "hybridtest/common/version.h"
#include "hybridtest/models/catalogue.h"
#include "hybridtest/multibody/kane.h"
