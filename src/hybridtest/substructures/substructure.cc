// See substructure.h: what every substructure does by default.
#include "hybridtest/substructures/substructure.h"

namespace hybridtest::substructures {

nlohmann::json MatrixJson(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index j = 0; j < m.cols(); ++j) row.push_back(m(i, j));
    rows.push_back(row);
  }
  return rows;
}

void Substructure::MeasureRequestedStiffness(nlohmann::json& entry) {
  const auto k0 = initial_stiffness();
  if (!k0) {
    entry.update({{"k0", nullptr}, {"source", "unknown"}});
    return;
  }
  const char* source = is_physical() ? "configured" : "law";
  if (num_slots() > 1) {
    entry.update({{"k0", MatrixJson(*k0)}, {"source", source}});
  } else {
    entry.update({{"k0", (*k0)(0, 0)}, {"source", source}});
  }
}

}  // namespace hybridtest::substructures
