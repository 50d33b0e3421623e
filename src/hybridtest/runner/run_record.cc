// See run_record.h.
#include "hybridtest/runner/run_record.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace hybridtest::runner {
namespace {

void AddPhysicalChannels(const std::string& slot, std::vector<io::Channel>& channels) {
  channels.push_back({slot + "_command", "m", "actuator command (absolute position) for " + slot});
  channels.push_back({slot + "_position", "m", "measured actuator position for " + slot});
  channels.push_back({slot + "_force", "N", "measured force (load-cell zero removed) for " + slot});
  channels.push_back({slot + "_lab_time", "s", "bench lab time at the sample for " + slot});
}

// "q3" if the slot's displacement is exactly one coordinate, else "".
std::string SlotCoordinate(const multibody::Model& model, int slot) {
  const auto& field = model.slots()[slot].displacement;
  if (field.is_affine() && field.terms().size() == 1 && field.terms()[0].coefficient == 1.0 &&
      field.constant() == 0.0 && field.time_rate() == 0.0) {
    return model.coordinates()[field.terms()[0].coordinate].name;
  }
  return "";
}

// A constraint's name as the stem of a channel name: letters, digits and _ kept.
std::string ChannelStem(const std::string& name) {
  std::string out = name;
  for (char& ch : out) {
    const bool keep = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                      (ch >= '0' && ch <= '9') || ch == '_';
    if (!keep) ch = '_';
  }
  return out;
}

void AddConstraintForceChannels(const multibody::Model& model,
                                std::vector<io::Channel>& channels) {
  for (int row : RecordedConstraintRows(model)) {
    const multibody::ConstraintRow& r = model.constraint_rows()[static_cast<std::size_t>(row)];
    const multibody::ConstraintSpec& c = model.constraints()[static_cast<std::size_t>(r.constraint)];
    std::string name = ChannelStem(c.name) + "_reaction";
    std::string description;
    if (c.components.empty()) {
      description = fmt::format("force of constraint '{}' (its multiplier λ)", c.name);
    } else {
      const char axis = "xyz"[r.component];
      name += std::string("_") + axis;
      const std::string& frame = model.frames()[static_cast<std::size_t>(c.expressed_in)].name;
      const std::string& point = model.points()[static_cast<std::size_t>(c.point)].name;
      description = c.kind == multibody::ConstraintSpec::Kind::kCoincident
          ? fmt::format("force of constraint '{}' on {} along {}.{} (−it on {})", c.name,
                        point, frame, axis,
                        model.points()[static_cast<std::size_t>(c.other)].name)
          : fmt::format("force of constraint '{}' on {} along {}.{}", c.name,
                        c.body >= 0 ? model.frames()[static_cast<std::size_t>(c.body)].name +
                                          " at " + point
                                    : point,
                        frame, axis);
    }
    channels.push_back({name, c.force_unit, description});
  }
}

}  // namespace

std::vector<int> RecordedConstraintRows(const multibody::Model& model) {
  std::vector<int> rows;
  for (int k = 0; k < model.num_constraint_rows(); ++k) {
    const int c = model.constraint_rows()[static_cast<std::size_t>(k)].constraint;
    if (model.constraints()[static_cast<std::size_t>(c)].record_force) rows.push_back(k);
  }
  return rows;
}

std::vector<io::Channel> JournalChannels(const io::RunSpec& spec) {
  const multibody::Model& model = spec.model.model;
  std::vector<io::Channel> channels{{"t", "s", "time"}};
  for (const auto& q : model.coordinates()) channels.push_back({q.name, q.unit, q.description});
  for (const auto& u : model.speeds()) channels.push_back({u.name, u.unit, u.description});
  for (const auto& z : model.extra_states()) channels.push_back({z.info.name, z.info.unit, z.info.description});
  for (const auto& s : model.slots()) channels.push_back({s.info.name, s.info.unit, s.info.description});
  for (const auto& sub : spec.substructures) {
    if (!sub.is_physical()) continue;
    for (const auto& name : sub.ActuatorNames()) AddPhysicalChannels(name, channels);
  }
  AddConstraintForceChannels(model, channels);
  return channels;
}

std::vector<io::Channel> StageChannels(const io::RunSpec& spec) {
  std::vector<io::Channel> channels{{"step", "-", "step index n (0-based)"},
                                    {"stage", "-", "Runge-Kutta stage (0-based)"},
                                    {"t", "s", "model time of the stage"}};
  for (const auto& sub : spec.substructures) {
    if (!sub.is_physical()) continue;
    for (const auto& slot : sub.ActuatorNames()) {
      AddPhysicalChannels(slot, channels);
      channels.push_back({slot + "_force_reversals", "-",
                          "reversals of the specimen force within the move (emulated bench) "
                          "for " + slot});
    }
  }
  return channels;
}

long MaxJournalRows(const io::RunSpec& spec) {
  const auto& sc = spec.scheme.config;
  double steps = static_cast<double>(spec.scheme.steps);
  if (sc.kind != schemes::SchemeKind::kRungeKutta && sc.adaptive.enabled) {
    steps = std::ceil(spec.scheme.duration / sc.adaptive.dt_min);
  }
  double rows = steps + 1.0;
  if (sc.kind == schemes::SchemeKind::kMrOs) rows += std::ceil(spec.scheme.duration / sc.substep) + steps;
  return static_cast<long>(std::min(rows, 1e15));
}

io::JournalMetadata JournalMetadataFor(const io::RunSpec& spec,
                                       const SubstructureList& subs, const std::string& command) {
  const multibody::Model& model = spec.model.model;
  io::JournalMetadata meta;
  meta.command = command;
  meta.config_path = spec.source.config_path;
  meta.config_text = spec.source.config_text;
  nlohmann::json parameters = nlohmann::json::array();
  for (const auto& p : spec.model.parameters.all()) {
    parameters.push_back({{"name", p.name}, {"value", p.value}, {"unit", p.unit},
                          {"description", p.description}});
  }
  auto infos = [](const std::vector<multibody::QuantityInfo>& list) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& q : list) {
      out.push_back({{"name", q.name}, {"unit", q.unit}, {"description", q.description}});
    }
    return out;
  };
  nlohmann::json slots = nlohmann::json::array();
  for (int s = 0; s < model.num_slots(); ++s) {
    slots.push_back({{"name", model.slots()[s].info.name},
                     {"unit", model.slots()[s].info.unit},
                     {"coordinate", SlotCoordinate(model, s)},
                     {"description", model.slots()[s].info.description}});
  }
  meta.model = {{"name", spec.model.name},      {"description", spec.model.description},
                {"blades", spec.source.blades},         {"parameters", parameters},
                {"coordinates", infos(model.coordinates())},
                {"speeds", infos(model.speeds())}, {"slots", slots}};
  if (model.num_extra_states() > 0) {
    std::vector<multibody::QuantityInfo> states;
    for (const auto& z : model.extra_states()) states.push_back(z.info);
    meta.model["extra_states"] = infos(states);
  }
  for (std::size_t s = 0; s < subs.size(); ++s) {
    const auto& sub = spec.substructures[s];
    const std::string slot = sub.slot;
    nlohmann::json entry = {{"slot", slot},
                            {"kind", subs[s]->is_physical() ? "physical" : "numerical"},
                            {"description", subs[s]->Describe()}};
    if (!sub.slots.empty()) entry["slots"] = sub.slots;
    const auto names = sub.ActuatorNames();
    if (subs[s]->is_physical() && names.size() == 1) {
      entry["channels"] = {{"command", slot + "_command"}, {"position", slot + "_position"},
                           {"force", slot + "_force"}, {"lab_time", slot + "_lab_time"}};
    } else if (subs[s]->is_physical()) {
      entry["channels"] = nlohmann::json::array();
      for (const auto& a : names) {
        entry["channels"].push_back({{"command", a + "_command"}, {"position", a + "_position"},
                                     {"force", a + "_force"}, {"lab_time", a + "_lab_time"}});
      }
    }
    meta.substructures.push_back(entry);
  }
  const schemes::SchemeConfig& scheme = spec.scheme.config;
  const integrators::ButcherTableau& tableau = spec.scheme.tableau;
  nlohmann::json integrator = {{"scheme", schemes::SchemeKindName(scheme.kind)}};
  if (scheme.kind == schemes::SchemeKind::kRungeKutta) {
    integrator.update({{"tableau", tableau.name}, {"title", tableau.title},
                       {"order", tableau.order}, {"stages", tableau.stages()}});
  } else {
    if (scheme.kind == schemes::SchemeKind::kAlphaOs) integrator["alpha"] = scheme.alpha;
    if (scheme.kind == schemes::SchemeKind::kMrOs) integrator["substep_s"] = scheme.substep;
    if (scheme.adaptive.enabled) {
      integrator["adaptive"] = {{"tolerance_m", scheme.adaptive.tolerance},
                                {"dt_min_s", scheme.adaptive.dt_min},
                                {"dt_max_s", scheme.adaptive.dt_max}};
    }
  }
  meta.extra = {{"integrator", integrator},
                {"dt", spec.scheme.dt},
                {"duration", spec.scheme.duration},
                {"steps", spec.scheme.steps}};
  if (!spec.source.test.empty()) meta.extra["test"] = spec.source.test;
  if (!spec.source.provenance.empty()) meta.extra["provenance"] = spec.source.provenance;
  return meta;
}

}  // namespace hybridtest::runner
