// See real_time_spec.h.
#include "hybridtest/io/real_time_spec.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"

namespace hybridtest::io {
namespace {

// The shortest tick a paced run takes. Unit: [s]. A paced loop cannot keep a shorter one on a
// general-purpose kernel, and the plant's delay line and the compensator's window are sized
// in ticks (at most 1 s / 10 µs and 10 s / 10 µs entries).
constexpr double kMinRealTimeTick = 1e-5;

// A real-time run steps once per tick of dt: integrator.dt must be at least kMinRealTimeTick.
void CheckTick(const YamlInput& in) {
  const YAML::Node& root = in.root();
  if (!root.IsMap() || !root["integrator"] || !root["integrator"].IsMap()) return;
  const YAML::Node dt = root["integrator"]["dt"];
  if (!dt.IsDefined() || !dt.IsScalar()) return;  // the integrator's reader reports it
  const double value = in.Number(dt, "integrator.dt", "a time step in seconds");
  if (value < kMinRealTimeTick) {
    in.ThrowValue(dt, "integrator.dt",
                  fmt::format("a tick of at least {:g} s for a real-time run (real_time:), the "
                              "shortest a paced loop keeps: enlarge dt or remove real_time:",
                              kMinRealTimeTick));
  }
}

}  // namespace

RealTimeSpec ReadRealTime(const YamlInput& in) {
  RealTimeSpec rt;
  const YAML::Node node = in.root()["real_time"];
  if (!node.IsDefined() || node.IsNull()) return rt;
  const std::string kp = "real_time";
  if (node.IsScalar() && node.Scalar() == "true") {
    rt.enabled = true;
    CheckTick(in);
    return rt;
  }
  in.RequireMapping(node, kp);
  in.CheckKeys(node, kp, {"clock", "hold_after_misses", "miss_tolerance", "lock_memory", "priority",
                          "cpu", "queue", "force"});
  rt.enabled = true;
  CheckTick(in);
  if (node["clock"]) {
    rt.clock = in.ReadString(node, kp, "clock", "");
    if (rt.clock != "wall" && rt.clock != "virtual") {
      in.ThrowValue(node["clock"], kp + ".clock",
                    "wall (paced by the computer's clock) or virtual (simulated time)");
    }
  }
  if (node["hold_after_misses"]) {
    rt.hold_after_misses = in.Count(node["hold_after_misses"], kp + ".hold_after_misses",
                                    "consecutive missed deadlines before a hold (0: never)", 0,
                                    1000000);
  }
  if (node["miss_tolerance"]) {
    rt.miss_tolerance = in.PositiveNumber(node["miss_tolerance"], kp + ".miss_tolerance",
                                          "the lateness of a tick that counts as a miss, in s");
  }
  auto flag = [&](const char* key, bool fallback) {
    const std::string v = in.ReadString(node, kp, key, fallback ? "true" : "false");
    if (v != "true" && v != "false") {
      in.ThrowValue(node[key], kp + "." + key, "true or false");
    }
    return v == "true";
  };
  rt.lock_memory = flag("lock_memory", true);
  rt.force = flag("force", false);
  if (node["priority"]) {
    rt.priority = static_cast<int>(in.Count(node["priority"], kp + ".priority",
                                            "a SCHED_FIFO priority 1..99, or 0", 0, 99));
  }
  if (node["cpu"]) {
    rt.cpu = static_cast<int>(in.Count(node["cpu"], kp + ".cpu", "a CPU index, or -1", -1, 4095));
  }
  if (node["queue"]) {
    rt.queue = in.Count(node["queue"], kp + ".queue", "a queue capacity in events", 64, 1 << 24);
  }
  return rt;
}

}  // namespace hybridtest::io
