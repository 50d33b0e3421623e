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
  if (a.p0) announced["p0_m"] = *a.p0;
  if (a.limits) {
    announced["limits"] = {{"stroke_min_m", a.limits->stroke_min},
                           {"stroke_max_m", a.limits->stroke_max},
                           {"max_increment_m", a.limits->max_increment},
                           {"force_soft_n", a.limits->force_soft},
                           {"force_hard_n", a.limits->force_hard}};
  }
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
