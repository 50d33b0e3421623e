#pragma once
// The entries of a planar model's mass matrix that do not depend on the state, and the
// columns of its Cholesky factor that follow from them alone (decision 0012, 1h).
//
// In a model planar about axis A (Model::planar_axis()), every frame E turns about e_A by
// θ_E = θ0_E + Σ_k w_k(E) q_k + c_t(E) t, with constant partial angular velocities w_k(E),
// and every point P is placed from its parent point in one frame E by an affine r(q, t). So
// the partial velocity of P for speed j is a sum of segments R_E a(q), one per step of P's
// chain, a = w_j(E) e_A × r + Σ (r's rate terms in q_j) coefficient e_c, each component of
// a affine in q. Then m V_j·V_k = m Σ a·R(θ_E' − θ_E) a', and a term a_c R_cd a'_d is
// constant when a_c or a'_d is a constant zero or both are constant and the two frames turn
// by the same w(E) and c_t(E) (a constant relative angle). M_jk is structurally constant when
// every such term of every mass element is, and the bodies' rotational part I_AA w_j w_k
// always is. Its value is the exact sum of the constants (e.g. a slide's m·1·1 = m, not the
// m(c² + s²) of the rotated columns).
#include <vector>


namespace hybridtest::multibody {

struct ConstantMassPlan {
  // n × n, column-major: 1 where M_jk is constant (both triangles), with its value.
  std::vector<char> entry;
  std::vector<double> value;  // 0 where not constant [kg, kg·m, kg·m²]
  // Per column j of L (M = L Lᵀ): 1 if every entry of L's column j and 1/L_jj follow from
  // constant entries of M alone; their values, in the layout of Data::cholesky_factor
  // (L(i, j) at factor[i n + j]) and Data::factor_inv_diag.
  std::vector<char> factor_column;
  std::vector<double> factor;
  std::vector<double> factor_inv_diag;
  bool any() const {
    for (char c : entry)
      if (c) return true;
    return false;
  }
};

}  // namespace hybridtest::multibody
