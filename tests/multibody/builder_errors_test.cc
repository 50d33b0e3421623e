// ModelBuilder rejects malformed models with a ModelError that names the element at fault.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/model.h"

namespace hybridtest::multibody {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// The message of the ModelError thrown by `f` ("" and a test failure if none is thrown).
template <class F>
std::string ErrorOf(F&& f) {
  try {
    f();
  } catch (const ModelError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a ModelError";
  return "";
}

ModelBuilder TwoCoordinates() { return ModelBuilder({{"q1", "m", ""}, {"q2", "rad", ""}}); }

TEST(BuilderErrorsTest, BadFrameIdNamesTheFrameAndTheId) {
  ModelBuilder b = TwoCoordinates();
  EXPECT_THAT(ErrorOf([&] {
                b.AddFrameAboutAxis("arm", FrameId{7}, Eigen::Vector3d::UnitZ(),
                                    ScalarField::Coordinate(1));
              }),
              AllOf(HasSubstr("frame 'arm'"), HasSubstr("frame id 7"), HasSubstr("1 frames")));
  EXPECT_THAT(ErrorOf([&] {
                b.AddPoint("tip", b.origin(), FrameId{-1}, {ScalarField::Constant(1.0), {}, {}});
              }),
              AllOf(HasSubstr("point 'tip'"), HasSubstr("frame id -1")));
  EXPECT_THAT(ErrorOf([&] {
                b.AddTorque("motor", FrameId{3}, b.newtonian(), [](const auto& a) {
                  using T = std::decay_t<decltype(a.t)>;
                  return Vector3<T>::Zero().eval();
                });
              }),
              AllOf(HasSubstr("load 'motor'"), HasSubstr("frame id 3")));
}

TEST(BuilderErrorsTest, BadPointIdNamesThePointAndTheId) {
  ModelBuilder b = TwoCoordinates();
  EXPECT_THAT(ErrorOf([&] {
                b.AddPoint("P2", PointId{5}, b.newtonian(), {ScalarField::Constant(1.0), {}, {}});
              }),
              AllOf(HasSubstr("point 'P2'"), HasSubstr("point id 5")));
  EXPECT_THAT(ErrorOf([&] { b.AddParticle("bob", PointId{2}, 1.0); }),
              AllOf(HasSubstr("particle 'bob'"), HasSubstr("point id 2")));
  EXPECT_THAT(ErrorOf([&] {
                b.AddRigidBody("disk", b.newtonian(), PointId{9}, 1.0,
                               Eigen::Matrix3d::Identity());
              }),
              AllOf(HasSubstr("rigid body 'disk'"), HasSubstr("point id 9")));
}

TEST(BuilderErrorsTest, NonPositiveParticleMassIsRejected) {
  for (double mass : {0.0, -1.5, std::nan("")}) {
    ModelBuilder b = TwoCoordinates();
    EXPECT_THAT(ErrorOf([&] { b.AddParticle("bob", b.origin(), mass); }),
                AllOf(HasSubstr("particle 'bob'"), HasSubstr("mass"), HasSubstr("positive")))
        << mass;
  }
}

TEST(BuilderErrorsTest, AsymmetricOrIndefiniteInertiaIsRejected) {
  ModelBuilder b = TwoCoordinates();
  Eigen::Matrix3d asymmetric = Eigen::Matrix3d::Identity();
  asymmetric(0, 1) = 0.1;
  EXPECT_THAT(ErrorOf([&] { b.AddRigidBody("disk", b.newtonian(), b.origin(), 1.0, asymmetric); }),
              AllOf(HasSubstr("rigid body 'disk'"), HasSubstr("symmetric")));
  const Eigen::Matrix3d indefinite = Eigen::Vector3d(1.0, -0.5, 1.0).asDiagonal();
  EXPECT_THAT(ErrorOf([&] { b.AddRigidBody("rotor", b.newtonian(), b.origin(), 1.0, indefinite); }),
              AllOf(HasSubstr("rigid body 'rotor'"), HasSubstr("negative principal moment"),
                    HasSubstr("-0.5")));
  EXPECT_THAT(ErrorOf([&] {
                b.AddRigidBody("heavy", b.newtonian(), b.origin(), -2.0,
                               Eigen::Matrix3d::Identity());
              }),
              AllOf(HasSubstr("rigid body 'heavy'"), HasSubstr("mass = -2")));
}

TEST(BuilderErrorsTest, TooManyOrNoCoordinatesAreRejected) {
  // The jets' cap applies to models with general fields only (here a W(q)), at Build().
  std::vector<QuantityInfo> many(kMaxJetCoordinates + 1, {"q", "m", ""});
  EXPECT_THAT(ErrorOf([&] {
                ModelBuilder b(many);
                b.AddParticle("p", b.AddPoint("P", b.origin(), b.newtonian(),
                                              {ScalarField::Coordinate(0), {}, {}}), 1.0);
                b.SetKinematicalEquations([](const auto&, auto W) {
                  for (auto& w : W) w = 0.0;
                });
                Model m = std::move(b).Build();
              }),
              AllOf(HasSubstr("at most 32"), HasSubstr("got 33")));
  EXPECT_THAT(ErrorOf([&] { ModelBuilder b({}); }), HasSubstr("at least one"));
  EXPECT_THAT(ErrorOf([&] { ModelBuilder b({{"q1", "m", ""}}, {{"u1", "", ""}, {"u2", "", ""}}); }),
              AllOf(HasSubstr("1 coordinates"), HasSubstr("2 speeds")));
  // The limit itself is accepted.
  std::vector<QuantityInfo> limit(kMaxJetCoordinates, {"q", "m", ""});
  EXPECT_NO_THROW(ModelBuilder b(limit));
}

TEST(BuilderErrorsTest, FieldReferringToAMissingCoordinateNamesTheElement) {
  ModelBuilder b = TwoCoordinates();
  EXPECT_THAT(ErrorOf([&] {
                b.AddPoint("tip", b.origin(), b.newtonian(),
                           {ScalarField::Constant(1.0), ScalarField::Coordinate(2), {}});
              }),
              AllOf(HasSubstr("point 'tip' component 1"), HasSubstr("coordinate index 2"),
                    HasSubstr("2 coordinates")));
  EXPECT_THAT(ErrorOf([&] {
                b.AddFrameAboutAxis("hub", b.newtonian(), Eigen::Vector3d::UnitZ(),
                                    ScalarField::Affine(0.0, {{0, 1.0}, {5, 2.0}}));
              }),
              AllOf(HasSubstr("frame 'hub' angle"), HasSubstr("coordinate index 5")));
  EXPECT_THAT(ErrorOf([&] { b.AddRestoringForceSlot("r1", "", ScalarField::Coordinate(4)); }),
              AllOf(HasSubstr("slot 'r1'"), HasSubstr("coordinate index 4")));
  EXPECT_THAT(ErrorOf([&] {
                b.AddFrameAboutAxis("arm", b.newtonian(), Eigen::Vector3d::UnitZ(),
                                    ScalarField::Coordinate(-1));
              }),
              AllOf(HasSubstr("frame 'arm' angle"), HasSubstr("negative coordinate index")));
}

TEST(BuilderErrorsTest, DuplicateSlotNameIsRejected) {
  ModelBuilder b = TwoCoordinates();
  EXPECT_EQ(b.AddRestoringForceSlot("r1", "first", ScalarField::Coordinate(0)), 0);
  EXPECT_THAT(ErrorOf([&] { b.AddRestoringForceSlot("r1", "again", ScalarField::Coordinate(1)); }),
              AllOf(HasSubstr("slot 'r1'"), HasSubstr("twice")));
}

TEST(BuilderErrorsTest, ModelWithoutMassIsRejected) {
  ModelBuilder b = TwoCoordinates();
  EXPECT_THAT(ErrorOf([&] { std::move(b).Build(); }), HasSubstr("no mass"));
}

TEST(BuilderErrorsTest, ZeroRotationAxisIsRejected) {
  ModelBuilder b = TwoCoordinates();
  EXPECT_THAT(ErrorOf([&] {
                b.AddFrameAboutAxis("A", b.newtonian(), Eigen::Vector3d::Zero(),
                                    ScalarField::Coordinate(0));
              }),
              AllOf(HasSubstr("frame 'A'"), HasSubstr("axis")));
}

}  // namespace
}  // namespace hybridtest::multibody

namespace hybridtest::multibody {
namespace {
// A DCM frame whose matrix is not a rotation (here a scaling by 2 for q ≠ 0) is refused by
// Build(), naming the frame.
TEST(BuilderErrorsTest, DcmThatIsNotARotationIsRefusedAtBuild) {
  ModelBuilder b({{"q1", "rad", ""}});
  const FrameId F = b.AddFrameWithDcm("F", b.newtonian(), DcmFunction([](const auto& a, auto R) {
    for (auto& r : R) r = 0.0;
    R[0] = 1.0 + a.q[0] * a.q[0];
    R[4] = 1.0;
    R[8] = 1.0;
  }));
  b.AddParticle("p", b.AddPoint("P", b.origin(), F, {ScalarField::Constant(1.0), {}, {}}), 1.0);
  try {
    Model m = std::move(b).Build();
    ADD_FAILURE() << "expected a ModelError";
  } catch (const ModelError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("frame 'F'"), HasSubstr("not a rotation")));
  }
}
}  // namespace
}  // namespace hybridtest::multibody
