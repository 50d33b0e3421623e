// Scaffold until the Session lands: runs the config with today's HybridTest into a temporary
// journal and prints what the Session example will print.
#include <cstdio>
#include <filesystem>

#include <hybridtest/io/config.h>
#include <hybridtest/io/run_reader.h>
#include <hybridtest/io/substructure_config.h>
#include <hybridtest/runner/hybrid_test.h>

namespace ht = hybridtest;

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const auto cfg = ht::io::LoadSimulationConfig(argv[1]);
  auto subs = ht::io::MakeSubstructures(cfg, {});
  ht::runner::RunOptions options;
  options.csv_path = (std::filesystem::temp_directory_path() / "step_a_session.csv").string();
  options.progress.mode = ht::runner::ProgressMode::kQuiet;
  std::filesystem::remove(options.csv_path);
  ht::runner::HybridTest test(cfg, std::move(subs), options);
  const auto s = test.Run();
  const auto run = ht::io::LoadRun(options.csv_path);
  for (long i = 0; i < run.num_rows(); i += 1000) std::printf("commit %ld: t = %g s\n", i, run.values(i, 0));
  for (int i = 1; i <= cfg.model.model.num_coordinates(); ++i)
    std::printf("  q%d = %.17g\n", i, run.values(run.num_rows() - 1, i));
  std::printf("statistics: %ld steps, %ld rows\n", s.steps, s.rows);
}
