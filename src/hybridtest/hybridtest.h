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
//
//   io/run_spec_yaml.h   LoadRunSpec: a run config (YAML) compiled once into an io::RunSpec
//   io/run_spec.h        RunSpec: everything a run needs, as plain data
//   runner/session.h     Session: Initialize(), Step(), observers, GetState()/SetState()
//   runner/open_run.h    OpenRun, OpenResume: the front door of a run that writes files
//                        (lock, guards, disk budget, input record, provenance); a file-backed
//                        Session is made from the OpenedRun they return
//   models/catalogue.h   the built-in models; multibody/kane.h the Kane engine
#include "hybridtest/common/error.h"
#include "hybridtest/common/units.h"
#include "hybridtest/common/version.h"
#include "hybridtest/io/run_spec.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/models/catalogue.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/runner/open_run.h"
#include "hybridtest/runner/session.h"
