#include "hybridtest/integrators/catalogue.h"

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <initializer_list>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "hybridtest/common/error.h"

namespace hybridtest::integrators {
namespace {

// Builds a tableau from the rows of a (only the entries left of the diagonal), b and c.
ButcherTableau Make(std::string name, std::string title, int order,
                    std::initializer_list<std::initializer_list<double>> a_lower,
                    std::initializer_list<double> b, std::initializer_list<double> c) {
  const auto s = static_cast<Eigen::Index>(b.size());
  ButcherTableau t;
  t.name = std::move(name);
  t.title = std::move(title);
  t.order = order;
  t.a = Eigen::MatrixXd::Zero(s, s);
  Eigen::Index i = 0;
  for (const auto& row : a_lower) {
    Eigen::Index j = 0;
    for (double v : row) t.a(i, j++) = v;
    ++i;
  }
  t.b = Eigen::Map<const Eigen::VectorXd>(b.begin(), s);
  t.c = Eigen::Map<const Eigen::VectorXd>(c.begin(), static_cast<Eigen::Index>(c.size()));
  return t;
}

std::vector<ButcherTableau> BuildCatalogue() {
  std::vector<ButcherTableau> all;
  all.push_back(Make("euler", "Forward Euler method", 1, {{}}, {1.0}, {0.0}));
  all.push_back(Make("heun", "Heun's method (explicit trapezoidal rule)", 2, {{}, {1.0}},
                     {0.5, 0.5}, {0.0, 1.0}));
  all.push_back(Make("midpoint", "Explicit midpoint rule", 2, {{}, {0.5}}, {0.0, 1.0},
                     {0.0, 0.5}));
  all.push_back(Make("ralston", "Ralston's second-order method", 2, {{}, {2.0 / 3.0}},
                     {0.25, 0.75}, {0.0, 2.0 / 3.0}));
  all.push_back(Make("rk3", "Kutta's third-order method", 3, {{}, {0.5}, {-1.0, 2.0}},
                     {1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0}, {0.0, 0.5, 1.0}));
  all.push_back(Make("rk4", "Classical fourth-order Runge-Kutta method", 4,
                     {{}, {0.5}, {0.0, 0.5}, {0.0, 0.0, 1.0}},
                     {1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0}, {0.0, 0.5, 0.5, 1.0}));
  all.push_back(Make("rk38", "Kutta's 3/8 rule (fourth order)", 4,
                     {{}, {1.0 / 3.0}, {-1.0 / 3.0, 1.0}, {1.0, -1.0, 1.0}},
                     {1.0 / 8.0, 3.0 / 8.0, 3.0 / 8.0, 1.0 / 8.0},
                     {0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0}));
  return all;
}

// Edit distance (insertions, deletions, substitutions), case-insensitive.
std::size_t EditDistance(std::string_view x, std::string_view y) {
  std::vector<std::size_t> row(y.size() + 1);
  for (std::size_t j = 0; j <= y.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= x.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= y.size(); ++j) {
      const bool same = std::tolower(static_cast<unsigned char>(x[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(y[j - 1]));
      const std::size_t next = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = row[j];
      row[j] = next;
    }
  }
  return row[y.size()];
}

}  // namespace

const std::vector<ButcherTableau>& Catalogue() {
  static const std::vector<ButcherTableau> catalogue = BuildCatalogue();
  return catalogue;
}

std::vector<std::string> TableauNames() {
  std::vector<std::string> names;
  for (const auto& t : Catalogue()) names.push_back(t.name);
  return names;
}

const ButcherTableau& FindTableau(std::string_view name) {
  const auto& catalogue = Catalogue();
  const ButcherTableau* closest = nullptr;
  std::size_t closest_distance = 0;
  for (const auto& t : catalogue) {
    if (t.name == name) return t;
    const std::size_t d = EditDistance(name, t.name);
    if (closest == nullptr || d < closest_distance) {
      closest = &t;
      closest_distance = d;
    }
  }
  throw ConfigError(fmt::format(
      "unknown integrator tableau '{}': expected one of {}; did you mean '{}'?", name,
      fmt::join(TableauNames(), ", "), closest->name));
}

}  // namespace hybridtest::integrators
