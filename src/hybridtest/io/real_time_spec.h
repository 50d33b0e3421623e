#pragma once
// RealTimeSpec: the `real_time:` block of a run config (docs/real-time.md). A run with the
// block is paced (runner/paced_loop.h): one fixed step of the scheme per tick of a clock. The
// Session reads the block and builds its pacer (runner/session.h); every front (the command
// line, Python, campaigns) steps the same Session::Run.
//
//   real_time:
//     clock: wall               # wall (the default) or virtual (simulated time, reproducible);
//                               # the command line's --clock and Python's clock= override it,
//                               # a campaign runs every case on the virtual clock
//     hold_after_misses: 10     # consecutive missed deadlines before the run holds (0: never)
//     miss_tolerance: 0.0005    # [s] a tick starting later than this after its deadline is a
//                               # miss (default: a quarter of the step)
//     lock_memory: true         # mlockall (wall clock only)
//     priority: 0               # SCHED_FIFO priority 1..99, 0: normal scheduling (wall clock)
//     cpu: -1                   # pin the stepping thread to this CPU, -1: no affinity
//     queue: 4096               # events the file observers may lag behind the loop
//     force: false              # run although the delay exceeds the critical delay
#include <optional>
#include <string>

#include "hybridtest/common/yaml_input.h"

namespace hybridtest::io {

struct RealTimeSpec {
  bool enabled = false;
  std::string clock;  // "wall", "virtual" or "" (wall); see above
  long hold_after_misses = 10;
  std::optional<double> miss_tolerance;  // [s]; unset: dt / 4
  bool lock_memory = true;
  int priority = 0;
  int cpu = -1;
  long queue = 4096;
  bool force = false;
};

// The `real_time:` block of the config's root (absent: disabled). Throws ConfigError naming
// the key and the fix.
RealTimeSpec ReadRealTime(const YamlInput& in);

}  // namespace hybridtest::io
