#pragma once
// Jet<T>: the value of a kinematic expression φ(q, t) together with what Kane's method needs
// from it along the current motion:
//   v   = φ                                   (value)
//   d1  = dφ/dt       = Σ_k ∂φ/∂q_k q̇_k + ∂φ/∂t
//   d2  = d²φ/dt² with u̇ = 0 (the remainder part; the u̇ part follows from dq and W)
//   dq  = ∂φ/∂q_k     (k = 0..n−1)             → partial rates ∂φ̇/∂u_j = Σ_k dq_k W_kj
// Arithmetic and elementary functions propagate all four by the chain rule, so a user can write
// any smooth kinematic expression (an angle, a position component, an entry of W(q)) as a
// generic lambda and the engine differentiates it exactly. Inline storage, no heap.
#include <array>
#include <cmath>

namespace hybridtest::multibody {

inline constexpr int kMaxJetCoordinates = 32;

template <typename T>
struct Jet {
  T v{0.0};
  T d1{0.0};
  T d2{0.0};
  int n = 0;  // number of active ∂/∂q entries
  std::array<T, kMaxJetCoordinates> dq{};

  Jet() = default;
  Jet(double c) : v(c) {}  // NOLINT: constants convert implicitly, as in ordinary arithmetic
};

namespace jet_detail {
// Applies φ(a) with φ' = f1, φ'' = f2 at a.v.
template <typename T>
Jet<T> Chain(const Jet<T>& a, const T& f0, const T& f1, const T& f2) {
  Jet<T> r;
  r.v = f0;
  r.d1 = f1 * a.d1;
  r.d2 = f2 * a.d1 * a.d1 + f1 * a.d2;
  r.n = a.n;
  for (int k = 0; k < a.n; ++k) r.dq[k] = f1 * a.dq[k];
  return r;
}
}  // namespace jet_detail

template <typename T>
Jet<T> operator+(const Jet<T>& a, const Jet<T>& b) {
  Jet<T> r;
  r.v = a.v + b.v;
  r.d1 = a.d1 + b.d1;
  r.d2 = a.d2 + b.d2;
  r.n = a.n > b.n ? a.n : b.n;
  for (int k = 0; k < r.n; ++k) r.dq[k] = (k < a.n ? a.dq[k] : T(0.0)) + (k < b.n ? b.dq[k] : T(0.0));
  return r;
}
template <typename T>
Jet<T> operator-(const Jet<T>& a) {
  Jet<T> r = a;
  r.v = -a.v;
  r.d1 = -a.d1;
  r.d2 = -a.d2;
  for (int k = 0; k < a.n; ++k) r.dq[k] = -a.dq[k];
  return r;
}
template <typename T>
Jet<T> operator-(const Jet<T>& a, const Jet<T>& b) { return a + (-b); }
template <typename T>
Jet<T> operator*(const Jet<T>& a, const Jet<T>& b) {
  Jet<T> r;
  r.v = a.v * b.v;
  r.d1 = a.d1 * b.v + a.v * b.d1;
  r.d2 = a.d2 * b.v + 2.0 * a.d1 * b.d1 + a.v * b.d2;
  r.n = a.n > b.n ? a.n : b.n;
  for (int k = 0; k < r.n; ++k)
    r.dq[k] = (k < a.n ? a.dq[k] * b.v : T(0.0)) + (k < b.n ? a.v * b.dq[k] : T(0.0));
  return r;
}
template <typename T>
Jet<T> Reciprocal(const Jet<T>& a) {
  using std::pow;
  const T inv = 1.0 / a.v;
  return jet_detail::Chain(a, inv, T(-inv * inv), T(2.0 * inv * inv * inv));
}
template <typename T>
Jet<T> operator/(const Jet<T>& a, const Jet<T>& b) { return a * Reciprocal(b); }

// Mixed operations with plain numbers, so that `l * cos(q)` reads naturally.
template <typename T> Jet<T> operator+(const Jet<T>& a, double c) { return a + Jet<T>(c); }
template <typename T> Jet<T> operator+(double c, const Jet<T>& a) { return Jet<T>(c) + a; }
template <typename T> Jet<T> operator-(const Jet<T>& a, double c) { return a - Jet<T>(c); }
template <typename T> Jet<T> operator-(double c, const Jet<T>& a) { return Jet<T>(c) - a; }
template <typename T> Jet<T> operator*(const Jet<T>& a, double c) {
  Jet<T> r = a;
  r.v *= c; r.d1 *= c; r.d2 *= c;
  for (int k = 0; k < a.n; ++k) r.dq[k] *= c;
  return r;
}
template <typename T> Jet<T> operator*(double c, const Jet<T>& a) { return a * c; }
template <typename T> Jet<T> operator/(const Jet<T>& a, double c) { return a * (1.0 / c); }
template <typename T> Jet<T> operator/(double c, const Jet<T>& a) { return Reciprocal(a) * c; }

template <typename T> Jet<T> sin(const Jet<T>& a) {
  using std::cos; using std::sin;
  const T s = sin(a.v), c = cos(a.v);
  return jet_detail::Chain(a, s, c, T(-s));
}
template <typename T> Jet<T> cos(const Jet<T>& a) {
  using std::cos; using std::sin;
  const T s = sin(a.v), c = cos(a.v);
  return jet_detail::Chain(a, c, T(-s), T(-c));
}
template <typename T> Jet<T> tan(const Jet<T>& a) {
  using std::tan;
  const T t = tan(a.v);
  const T sec2 = 1.0 + t * t;
  return jet_detail::Chain(a, t, sec2, T(2.0 * t * sec2));
}
template <typename T> Jet<T> exp(const Jet<T>& a) {
  using std::exp;
  const T e = exp(a.v);
  return jet_detail::Chain(a, e, e, e);
}
template <typename T> Jet<T> log(const Jet<T>& a) {
  using std::log;
  const T inv = 1.0 / a.v;
  return jet_detail::Chain(a, T(log(a.v)), inv, T(-inv * inv));
}
template <typename T> Jet<T> sqrt(const Jet<T>& a) {
  using std::sqrt;
  const T s = sqrt(a.v);
  return jet_detail::Chain(a, s, T(0.5 / s), T(-0.25 / (s * a.v)));
}
template <typename T> Jet<T> pow(const Jet<T>& a, double p) {
  using std::pow;
  // pow(v, 0) is the constant 1: for AutoDiff, pow(v, 0)'s own derivative 0 · v^−1 is NaN at
  // v = 0 (e.g. x² at x = 0). For double the values are the same as pow's.
  const T d1 = p == 1.0 ? T(1.0) : T(p * pow(a.v, p - 1.0));
  const T d2 = p == 2.0 ? T(2.0) : p == 1.0 ? T(0.0) : T(p * (p - 1.0) * pow(a.v, p - 2.0));
  return jet_detail::Chain(a, T(pow(a.v, p)), d1, d2);
}

}  // namespace hybridtest::multibody
