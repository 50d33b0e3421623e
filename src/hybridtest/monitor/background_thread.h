#pragma once
// Keeps the monitor's threads (the HTTP server's and the collector's) out of the stepping
// thread's way on a real-time run. Called on the thread itself, first thing:
//   - SCHED_IDLE: the kernel gives the thread a core only when nothing else wants it, so a
//     viewer's request never takes time from the paced loop on the core they share. A
//     thread created by a SCHED_FIFO stepping thread (which it would inherit) drops it too.
//   - if the stepping thread is pinned (`real_time.cpu`), the thread's CPU affinity is every
//     allowed CPU but that one (kept as it is if that one is the only one).
// Unprivileged: lowering a thread's own policy needs no capability. Returns what was done,
// for the log ("SCHED_IDLE, CPUs 0 2 3"), or why not.
#include <string>

namespace hybridtest::monitor {

std::string MoveThisThreadToBackground(int avoid_cpu);

}  // namespace hybridtest::monitor
