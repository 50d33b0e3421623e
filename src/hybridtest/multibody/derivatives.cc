// Chunked forward-mode derivatives of the equations of motion. See derivatives.h.
#include "hybridtest/multibody/derivatives.h"

#include <fmt/core.h>

#include <algorithm>

#include "hybridtest/common/error.h"

namespace hybridtest::multibody {

DerivativeWorkspace::DerivativeWorkspace(const Model& model)
    : data(model),
      x(model.num_states()),
      r(model.num_slots()),
      xdot(model.num_states()) {}

namespace {
void CheckSize(Eigen::Index rows, Eigen::Index cols, Eigen::Index want_rows,
               Eigen::Index want_cols, const char* what) {
  if (rows != want_rows || cols != want_cols) {
    throw ModelError(fmt::format("{}: expected {} × {}, got {} × {}", what, want_rows, want_cols,
                                 rows, cols));
  }
}
}  // namespace

void CalcStateJacobian(const Model& model, DerivativeWorkspace& ws, double t,
                       const Eigen::Ref<const Eigen::VectorXd>& x,
                       const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Ref<Eigen::MatrixXd> J) {
  const int nx = model.num_states();
  CheckSize(x.size(), 1, nx, 1, "CalcStateJacobian: x");
  CheckSize(r.size(), 1, model.num_slots(), 1, "CalcStateJacobian: r");
  CheckSize(J.rows(), J.cols(), nx, nx, "CalcStateJacobian: J");
  // Columns c0 … c0+m−1 of J per AutoDiff evaluation; every input carries m derivatives
  // (Eigen's AutoDiffScalar cannot mix derivative vectors of different sizes).
  for (int c0 = 0; c0 < nx; c0 += kMaxDerivatives) {
    const int m = std::min(kMaxDerivatives, nx - c0);
    for (int i = 0; i < nx; ++i) {
      ws.x(i).value() = x(i);
      ws.x(i).derivatives().setZero(m);
      if (i >= c0 && i < c0 + m) ws.x(i).derivatives()(i - c0) = 1.0;
    }
    for (Eigen::Index s = 0; s < r.size(); ++s) {
      ws.r(s).value() = r(s);
      ws.r(s).derivatives().setZero(m);
    }
    const AutoDiff ta(t, Derivatives::Zero(m));
    CalcStateDerivative<AutoDiff>(model, ws.data, ta, ws.x, ws.r, ws.xdot);
    for (int i = 0; i < nx; ++i) {
      const Derivatives& d = ws.xdot(i).derivatives();
      for (int k = 0; k < m; ++k) J(i, c0 + k) = d.size() > k ? d(k) : 0.0;
    }
  }
}

void CalcCouplingMatrix(const Model& model, DerivativeWorkspace& ws, double t,
                        const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::MatrixXd> B) {
  const int n = model.num_coordinates();
  const int nx = model.num_states();
  const int ns = model.num_slots();
  CheckSize(x.size(), 1, nx, 1, "CalcCouplingMatrix: x");
  CheckSize(B.rows(), B.cols(), n, ns, "CalcCouplingMatrix: B");
  for (int c0 = 0; c0 < ns; c0 += kMaxDerivatives) {
    const int m = std::min(kMaxDerivatives, ns - c0);
    for (int i = 0; i < nx; ++i) {
      ws.x(i).value() = x(i);
      ws.x(i).derivatives().setZero(m);
    }
    for (int s = 0; s < ns; ++s) {
      ws.r(s).value() = 0.0;
      ws.r(s).derivatives().setZero(m);
      if (s >= c0 && s < c0 + m) ws.r(s).derivatives()(s - c0) = 1.0;
    }
    const AutoDiff ta(t, Derivatives::Zero(m));
    CalcKinematics<AutoDiff>(model, ws.data, ta, ws.x);
    CalcForcing<AutoDiff>(model, ws.data, ws.r);
    for (int j = 0; j < n; ++j) {
      const Derivatives& d = ws.data.g(j).derivatives();
      for (int k = 0; k < m; ++k) B(j, c0 + k) = d.size() > k ? d(k) : 0.0;
    }
  }
}

// The allocating forms (kane.h): a workspace per call.
Eigen::MatrixXd CalcCouplingMatrix(const Model& model, double t, const Eigen::VectorXd& x) {
  DerivativeWorkspace ws(model);
  Eigen::MatrixXd B(model.num_coordinates(), model.num_slots());
  CalcCouplingMatrix(model, ws, t, x, B);
  return B;
}

Eigen::MatrixXd CalcStateJacobian(const Model& model, double t, const Eigen::VectorXd& x,
                                  const Eigen::VectorXd& r) {
  DerivativeWorkspace ws(model);
  Eigen::MatrixXd J(model.num_states(), model.num_states());
  CalcStateJacobian(model, ws, t, x, r, J);
  return J;
}

}  // namespace hybridtest::multibody
