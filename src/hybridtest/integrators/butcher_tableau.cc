#include "hybridtest/integrators/butcher_tableau.h"

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "hybridtest/common/error.h"

namespace hybridtest::integrators {
namespace {

// Prefix of every message: where the tableau came from and which one it is.
std::string Prefix(const ButcherTableau& tableau, std::string_view where) {
  if (tableau.name.empty()) return fmt::format("{}: Butcher tableau", where);
  return fmt::format("{}: Butcher tableau '{}'", where, tableau.name);
}

void CheckShapes(const ButcherTableau& t, std::string_view where) {
  const auto s = t.b.size();
  if (s == 0) {
    throw ConfigError(fmt::format(
        "{}: expected at least one stage, given an empty weight vector b; give b with s "
        "entries, a as s × s and c with s entries",
        Prefix(t, where)));
  }
  if (t.a.rows() != s || t.a.cols() != s || t.c.size() != s) {
    throw ConfigError(fmt::format(
        "{}: shapes disagree: b has {} entries, so expected a to be {} × {} and c to have {} "
        "entries; given a {} × {} and c with {} entries; make a square with one row per weight",
        Prefix(t, where), s, s, s, s, t.a.rows(), t.a.cols(), t.c.size()));
  }
}

void CheckFinite(const ButcherTableau& t, std::string_view where) {
  const auto s = t.b.size();
  for (Eigen::Index i = 0; i < s; ++i) {
    for (Eigen::Index j = 0; j < s; ++j) {
      if (!std::isfinite(t.a(i, j))) {
        throw ConfigError(fmt::format("{}: a[{}][{}] = {}: expected a finite number",
                                      Prefix(t, where), i, j, t.a(i, j)));
      }
    }
    if (!std::isfinite(t.b(i))) {
      throw ConfigError(fmt::format("{}: b[{}] = {}: expected a finite number", Prefix(t, where),
                                    i, t.b(i)));
    }
    if (!std::isfinite(t.c(i))) {
      throw ConfigError(fmt::format("{}: c[{}] = {}: expected a finite number", Prefix(t, where),
                                    i, t.c(i)));
    }
  }
}

void CheckOrderClaim(const ButcherTableau& t, std::string_view where) {
  if (t.order < 1) {
    throw ConfigError(fmt::format(
        "{}: order = {}: expected the classical order p ≥ 1 that the method claims",
        Prefix(t, where), t.order));
  }
  if (t.order > kMaxCheckedOrder) {
    throw ConfigError(fmt::format(
        "{}: order = {}: claims of order above {} are not supported (their order conditions "
        "are not checked); claim order {} or less",
        Prefix(t, where), t.order, kMaxCheckedOrder, kMaxCheckedOrder));
  }
}

void CheckExplicit(const ButcherTableau& t, std::string_view where) {
  const auto s = t.b.size();
  for (Eigen::Index i = 0; i < s; ++i) {
    for (Eigen::Index j = i; j < s; ++j) {
      if (t.a(i, j) != 0.0) {
        throw ConfigError(fmt::format(
            "{}: a[{}][{}] = {}: expected a strictly lower triangular a (a[i][j] = 0 for "
            "j ≥ i), since only explicit methods are supported; set it to 0",
            Prefix(t, where), i, j, t.a(i, j)));
      }
    }
  }
}

void CheckNodes(const ButcherTableau& t, std::string_view where) {
  const Eigen::VectorXd row_sums = t.a.rowwise().sum();
  for (Eigen::Index i = 0; i < t.b.size(); ++i) {
    if (std::abs(t.c(i) - row_sums(i)) > kTableauTolerance) {
      throw ConfigError(fmt::format(
          "{}: c[{}] = {}: expected c[{}] = Σ_j a[{}][j] = {:.17g} (tolerance {:g}); set c[{}] "
          "to the row sum of a",
          Prefix(t, where), i, t.c(i), i, i, row_sums(i), kTableauTolerance, i));
    }
  }
}

// One order condition Σ(...) = expected, belonging to order p.
void CheckCondition(const ButcherTableau& t, std::string_view where, int p,
                    std::string_view formula, double value, double expected,
                    std::string_view expected_text) {
  if (std::abs(value - expected) > kTableauTolerance) {
    throw ConfigError(fmt::format(
        "{}: claims order {} but violates the order-{} condition {} = {}: given {:.17g} "
        "(tolerance {:g}); lower the claimed order or correct a, b, c (give entries to full "
        "double precision)",
        Prefix(t, where), t.order, p, formula, expected_text, value, kTableauTolerance));
  }
}

void CheckOrderConditions(const ButcherTableau& t, std::string_view where) {
  const Eigen::VectorXd& b = t.b;
  const Eigen::VectorXd& c = t.c;
  const Eigen::MatrixXd& a = t.a;
  const int p = t.order;

  CheckCondition(t, where, 1, "Σ b_i", b.sum(), 1.0, "1");
  if (p < 2) return;
  CheckCondition(t, where, 2, "Σ b_i c_i", b.dot(c), 1.0 / 2.0, "1/2");
  if (p < 3) return;
  const Eigen::VectorXd c2 = c.array().square();
  const Eigen::VectorXd ac = a * c;
  CheckCondition(t, where, 3, "Σ b_i c_i²", b.dot(c2), 1.0 / 3.0, "1/3");
  CheckCondition(t, where, 3, "Σ b_i a_ij c_j", b.dot(ac), 1.0 / 6.0, "1/6");
  if (p < 4) return;
  const Eigen::VectorXd c3 = c.array().cube();
  const Eigen::VectorXd bc = b.cwiseProduct(c);
  CheckCondition(t, where, 4, "Σ b_i c_i³", b.dot(c3), 1.0 / 4.0, "1/4");
  CheckCondition(t, where, 4, "Σ b_i c_i a_ij c_j", bc.dot(ac), 1.0 / 8.0, "1/8");
  CheckCondition(t, where, 4, "Σ b_i a_ij c_j²", b.dot(a * c2), 1.0 / 12.0, "1/12");
  CheckCondition(t, where, 4, "Σ b_i a_ij a_jk c_k", b.dot(a * ac), 1.0 / 24.0, "1/24");
}

}  // namespace

void ValidateTableau(const ButcherTableau& tableau, std::string_view where) {
  CheckShapes(tableau, where);
  CheckFinite(tableau, where);
  CheckExplicit(tableau, where);
  CheckNodes(tableau, where);
  CheckOrderClaim(tableau, where);
  CheckOrderConditions(tableau, where);
}

}  // namespace hybridtest::integrators
