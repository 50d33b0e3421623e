#pragma once
// A transfer system of two (or n) actuators, each an ideal rt_plant with a linear specimen and
// an optional pure delay (SI): the paced bench of a specimen on several actuators for the
// real-time tests. It counts StartPaced calls
// so that a test sees that every actuator was paced.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/transfer/rt_plant.h"

namespace hybridtest::runner::test {

class PlantPair final : public transfer::TransferSystem {
 public:
  // stiffness k_k [N/m], zero-force position p0_k [m] and pure delay τ_k [s] (none: 0) of
  // each actuator's plant and specimen.
  PlantPair(std::vector<double> stiffness, std::vector<double> p0, int* paced = nullptr,
            std::vector<double> delay = {})
      : paced_(paced) {
    for (std::size_t k = 0; k < stiffness.size(); ++k) {
      transfer::RtPlantConfig c;
      c.kind = transfer::PlantKind::kIdeal;
      c.one().p0 = p0[k];
      c.one().delay = k < delay.size() ? delay[k] : 0.0;
      c.specimen.stiffness = {stiffness[k]};
      plants_.push_back(std::make_unique<transfer::RtPlant>(c));
    }
  }
  void Activate() override {
    for (auto& p : plants_) p->Activate();
  }
  int num_actuators() const override { return static_cast<int>(plants_.size()); }
  void Execute(std::span<const double> commands, std::span<transfer::Measurement> out) override {
    for (std::size_t k = 0; k < plants_.size(); ++k) out[k] = ExecuteOne(*plants_[k], commands[k]);
  }
  void Hold() noexcept override {
    for (auto& p : plants_) p->Hold();
  }
  void Deactivate() override {
    for (auto& p : plants_) p->Deactivate();
  }
  transfer::BenchUnits bench_units() const override { return {}; }
  std::string Describe() const override { return "two ideal rt_plants"; }
  void StartPaced(double tick, const Clock& clock) override {
    for (auto& p : plants_) {
      p->StartPaced(tick, clock);
      if (paced_ != nullptr) ++*paced_;
    }
  }
  bool can_run_paced() const override { return true; }
  std::optional<double> PhaseDelay(double omega, double tick) const override {
    double worst = 0.0;
    for (const auto& p : plants_) worst = std::max(worst, *p->PhaseDelay(omega, tick));
    return worst;
  }
  std::optional<long> commands_received() const override {
    return plants_[0]->commands_received();
  }
  const transfer::RtPlant& plant(int k) const { return *plants_[static_cast<std::size_t>(k)]; }

 private:
  std::vector<std::unique_ptr<transfer::RtPlant>> plants_;
  int* paced_;
};

}  // namespace hybridtest::runner::test
