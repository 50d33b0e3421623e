// The live monitor's cost to the run's loop (docs/monitor.md), on the paper's emulated run
// (examples/rotor/emulated.yaml: 10 s, 10,000 steps, the in-process emulated bench, no files):
// every iteration runs it twice, without a monitor (the reference) and with the monitor and
// its HTTP server and N viewers polling like the page (GET /api/state at 2 Hz, /api/series at
// 1 Hz), or, for "stress", every 10 ms. Interleaved, so that both see the same machine.
//
//   Monitor/Overhead/viewers:N[/stress]   time of the monitored run (manual time)
//     counters: ratio = monitored / reference wall time (same iterations); cpu_ratio = the
//     same for the stepping thread's own CPU time (what the loop itself pays, apart from
//     what other processes take from a shared machine); dropped = frames the ring dropped (a
//     viewer never holds the run up; frames are dropped instead)
#include <benchmark/benchmark.h>
#include <time.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "hybridtest/io/config.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/monitor/monitor_observer.h"
#include "hybridtest/monitor/monitor_server.h"
#include "hybridtest/monitor/operator_control.h"
#include "hybridtest/runner/session.h"
// After Eigen: <resolv.h>, which httplib includes, defines `_res`.
#include <httplib.h>

namespace hybridtest {
namespace {

using Clock = std::chrono::steady_clock;

io::RunSpec EmulatedSpec(const io::SimulationConfig& cfg) {
  io::RunSpec spec = io::CompileRunSpec(cfg);
  spec.output.files = false;
  spec.quiet = true;
  return spec;
}

double Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// CPU time of the calling thread [s].
double ThreadCpu() {
  timespec ts{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// `count` viewers polling `port` every `period` (state) and 2 × period (series) until stopped.
class Viewers {
 public:
  Viewers(int count, std::uint16_t port, std::chrono::milliseconds period) {
    for (int v = 0; v < count; ++v) {
      threads_.emplace_back([this, port, period] {
        httplib::Client client("127.0.0.1", port);
        long since = -1, generation = -1;
        for (long k = 0; !stop_.load(); ++k) {
          if (auto r = client.Get("/api/state")) benchmark::DoNotOptimize(r->body.size());
          if (k % 2 == 0) {
            const std::string path = "/api/series?since=" + std::to_string(since) +
                                     "&generation=" + std::to_string(generation);
            if (auto r = client.Get(path.c_str())) {
              const auto j = nlohmann::json::parse(r->body, nullptr, false);
              if (j.is_object() && !j["columns"]["seq"].empty()) {
                since = j["columns"]["seq"].back().get<long>();
                generation = j["generation"].get<long>();
              }
            }
          }
          std::this_thread::sleep_for(period);
        }
      });
    }
  }
  ~Viewers() {
    stop_ = true;
    for (auto& t : threads_) t.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::vector<std::thread> threads_;
};

void BM_MonitorOverhead(benchmark::State& state) {
  const int viewers = static_cast<int>(state.range(0));
  const std::chrono::milliseconds period(state.range(1));
  const io::SimulationConfig cfg =
      io::LoadSimulationConfig(std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/rotor/emulated.yaml");
  double reference_s = 0.0, monitored_s = 0.0, reference_cpu = 0.0, monitored_cpu = 0.0;
  long dropped = 0;
  for (auto _ : state) {
    {
      runner::Session session(EmulatedSpec(cfg));
      const auto start = Clock::now();
      const double cpu = ThreadCpu();
      session.Run();
      reference_cpu += ThreadCpu() - cpu;
      reference_s += Seconds(start);
    }
    monitor::MonitorState monitor_state;
    monitor::MonitorObserver observer(monitor_state);
    monitor::OperatorControl control(monitor_state);
    monitor::MonitorServer server(monitor_state, &control, {});
    server.Start();
    runner::Session session(EmulatedSpec(cfg));
    session.AddObserver(observer);
    {
      Viewers polling(viewers, server.port(), period);
      const auto start = Clock::now();
      const double cpu = ThreadCpu();
      runner::StepResult result = session.Initialize();
      while (result.status == runner::SessionStatus::kWorking) {
        result = control.BetweenSteps(session);
        if (result.status == runner::SessionStatus::kWorking) result = session.Step();
      }
      monitored_cpu += ThreadCpu() - cpu;
      const double s = Seconds(start);
      monitored_s += s;
      state.SetIterationTime(s);
    }
    dropped += observer.dropped();
  }
  state.counters["ratio"] = monitored_s / reference_s;
  state.counters["cpu_ratio"] = monitored_cpu / reference_cpu;
  state.counters["reference_s"] = reference_s / static_cast<double>(state.iterations());
  state.counters["dropped"] = static_cast<double>(dropped);
}
BENCHMARK(BM_MonitorOverhead)
    ->Name("Monitor/Overhead")
    ->ArgNames({"viewers", "period_ms"})
    ->Args({0, 500})
    ->Args({1, 500})
    ->Args({10, 500})
    ->Args({10, 10})
    ->Iterations(5)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hybridtest
