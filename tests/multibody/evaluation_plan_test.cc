// The evaluation plan of Data<double> (data.h, EvaluationPlan): addresses into the workspace
// for the grouped sums and, for planar models, the constant partial angular velocities and
// rotational mass terms. A workspace that was copied, moved or assigned must evaluate with its
// own buffers, and a workspace used with another model of the same shape must evaluate that
// model: every case is compared with a fresh workspace, entry by entry (exact: the same
// operations in the same order).
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <utility>

#include "hybridtest/multibody/kane.h"
#include "support/multibody_helpers.h"

namespace hybridtest::multibody {
namespace {

using test_support::CoordinateScales;
using test_support::DefaultModel;
using test_support::RandomForces;
using test_support::RandomState;

struct Evaluation {
  Eigen::VectorXd xdot;
  Eigen::MatrixXd M;
  Eigen::VectorXd g;
};

Evaluation Evaluate(const Model& model, Data<double>& data, double t, const Eigen::VectorXd& x,
                    const Eigen::VectorXd& r) {
  Evaluation e{Eigen::VectorXd(model.num_states()), {}, {}};
  CalcStateDerivative<double>(model, data, t, x, r, e.xdot);
  e.M = data.M;
  e.g = data.g;
  return e;
}

void ExpectSame(const Evaluation& a, const Evaluation& b, const std::string& what) {
  EXPECT_TRUE(a.xdot == b.xdot) << what << ": ẋ " << a.xdot.transpose() << " vs "
                                << b.xdot.transpose();
  EXPECT_TRUE(a.M == b.M) << what << ": M\n" << a.M << "\nvs\n" << b.M;
  EXPECT_TRUE(a.g == b.g) << what << ": g " << a.g.transpose() << " vs " << b.g.transpose();
}

// The copy is evaluated at a state other than the one its source last saw: a plan still
// pointing into the source would read the source's partial velocities and loads.
TEST(EvaluationPlan, CopiedMovedAndAssignedWorkspacesUseTheirOwnBuffers) {
  std::mt19937 rng(5);
  for (const std::string& name : models::ModelNames()) {
    SCOPED_TRACE(name);
    const models::BuiltModel built = DefaultModel(name);
    const Model& model = built.model;
    const Eigen::VectorXd x1 = RandomState(rng, CoordinateScales(built), 2.0);
    const Eigen::VectorXd x2 = RandomState(rng, CoordinateScales(built), 2.0);
    const Eigen::VectorXd r1 = RandomForces(rng, model.num_slots(), 100.0);
    const Eigen::VectorXd r2 = RandomForces(rng, model.num_slots(), 100.0);
    Data<double> fresh(model);
    const Evaluation expected = Evaluate(model, fresh, 0.4, x2, r2);

    Data<double> source(model);
    Evaluate(model, source, 0.1, x1, r1);
    Data<double> copy(source);
    ExpectSame(Evaluate(model, copy, 0.4, x2, r2), expected, "copy");
    Data<double> assigned(model);
    Evaluate(model, assigned, 0.2, x2, r1);
    assigned = source;
    ExpectSame(Evaluate(model, assigned, 0.4, x2, r2), expected, "assigned");
    Data<double> moved(std::move(copy));
    ExpectSame(Evaluate(model, moved, 0.4, x2, r2), expected, "moved");
    // The source still evaluates with its own buffers after all that.
    ExpectSame(Evaluate(model, source, 0.4, x2, r2), expected, "source");
  }
}

// The rotor with another hub inertia and blade mass: the same shape (so a workspace of one
// fits the other), other grouped mass terms and another constant rotational term of M; then
// the same with the other model assigned into the first one's object.
TEST(EvaluationPlan, WorkspaceUsedWithAnotherModelOfTheSameShape) {
  const models::BuiltModel first = DefaultModel("rotor");
  models::ParameterSet parameters = models::DefaultParameters("rotor", 3);
  parameters.Set("I_g", 2.0 * parameters.Get("I_g"), "test");
  parameters.Set("blade2.m_b", 1.5 * parameters.Get("m_b"), "test");
  const models::BuiltModel second = models::BuildModel("rotor", 3, parameters);
  std::mt19937 rng(9);
  const Eigen::VectorXd x = RandomState(rng, CoordinateScales(first), 2.0);
  const Eigen::VectorXd r = RandomForces(rng, first.model.num_slots(), 100.0);
  Data<double> fresh(second.model);
  const Evaluation expected = Evaluate(second.model, fresh, 0.3, x, r);
  Data<double> shared(first.model);
  const Evaluation of_first = Evaluate(first.model, shared, 0.3, x, r);
  EXPECT_NE(of_first.M(3, 3), expected.M(3, 3));  // the two models differ where it shows
  ExpectSame(Evaluate(second.model, shared, 0.3, x, r), expected, "second model");
  ExpectSame(Evaluate(first.model, shared, 0.3, x, r), of_first, "first model again");
  // The other model assigned into the same object (the same address): its content is new.
  models::BuiltModel reassigned = DefaultModel("rotor");
  Data<double> kept(reassigned.model);
  ExpectSame(Evaluate(reassigned.model, kept, 0.3, x, r), of_first, "before the assignment");
  const std::uint64_t id = reassigned.model.instance_id();
  reassigned.model = second.model;
  EXPECT_NE(reassigned.model.instance_id(), id);
  EXPECT_NE(reassigned.model.instance_id(), second.model.instance_id());
  ExpectSame(Evaluate(reassigned.model, kept, 0.3, x, r), expected, "after the assignment");
}

}  // namespace
}  // namespace hybridtest::multibody
