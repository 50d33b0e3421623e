// See bench_record.h.
#include "hybridtest/runner/bench_record.h"


namespace hybridtest::runner {
namespace {

nlohmann::json Record(const transfer::TransferSystem& bench, nlohmann::json slots) {
  const transfer::BenchUnits units = bench.bench_units();
  nlohmann::json entry = {{"slots", std::move(slots)},
                          {"description", bench.Describe()},
                          {"units", {{"length", units.length_name},
                                     {"force", units.force_name},
                                     {"metres_per_length_unit", units.metres_per_length_unit},
                                     {"newtons_per_force_unit", units.newtons_per_force_unit}}}};
  const transfer::BenchAnnouncement a = bench.Announce();
  nlohmann::json announced = nlohmann::json::object();
  if (!a.source.empty()) announced["source"] = a.source;
  nlohmann::json actuators = nlohmann::json::array();
  for (const transfer::ActuatorAnnouncement& k : a.actuators) {
    nlohmann::json actuator = nlohmann::json::object();
    if (k.p0) actuator["p0_m"] = *k.p0;
    if (k.limits) {
      actuator["limits"] = {{"stroke_min_m", k.limits->stroke_min},
                            {"stroke_max_m", k.limits->stroke_max},
                            {"max_increment_m", k.limits->max_increment},
                            {"force_soft_n", k.limits->force_soft},
                            {"force_hard_n", k.limits->force_hard}};
    }
    actuators.push_back(std::move(actuator));
  }
  if (!a.actuators.empty()) announced["actuators"] = std::move(actuators);
  if (!announced.empty()) entry["announced"] = std::move(announced);
  return entry;
}

}  // namespace

nlohmann::json BenchRecords(const SubstructureList& subs, const io::RunSpec& spec) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t s = 0; s < subs.size(); ++s) {
    const auto* sub = subs[s].get();
    const nlohmann::json slots = s < spec.substructures.size()
                                     ? nlohmann::json(spec.substructures[s].SlotNames())
                                     : nlohmann::json::array();
    if (const transfer::TransferSystem* t = sub->transfer_system()) {
      out.push_back(Record(*t, slots));
    }
  }
  return out;
}

}  // namespace hybridtest::runner
