// Model files: kinematical equations, frames, points, particles and rigid bodies. See
// model_file.h and docs/model-files.md.
#include <fmt/core.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/expression_eval.h"
#include "hybridtest/modelfile/file_context.h"
#include "hybridtest/modelfile/names.h"

namespace hybridtest::modelfile::internal {

using multibody::FrameId;
using multibody::PointId;

namespace {
// Runs a builder call; a ModelError it throws is re-thrown as a ConfigError at `where`.
template <class F>
auto AtPlace(const std::string& where, F&& f) {
  try {
    return f();
  } catch (const ModelError& e) {
    throw ConfigError(fmt::format("{}: {}", where, e.what()));
  }
}

// A 3-vector of constants, or "x", "y", "z" for a unit axis.
Eigen::Vector3d Axis(const FileContext& c, const YAML::Node& node, const std::string& kp) {
  if (node.IsScalar()) {
    const std::string s = node.Scalar();
    if (s == "x" || s == "X") return Eigen::Vector3d::UnitX();
    if (s == "y" || s == "Y") return Eigen::Vector3d::UnitY();
    if (s == "z" || s == "Z") return Eigen::Vector3d::UnitZ();
  }
  if (!node.IsSequence() || node.size() != 3) {
    c.in.ThrowValue(node, kp, "x, y, z or a vector [ax, ay, az] in the parent frame");
  }
  Eigen::Vector3d a;
  for (int i = 0; i < 3; ++i) {
    a(i) = c.Constant(node[i], fmt::format("{}[{}]", kp, i), "an axis component");
  }
  return a;
}

// A 3 × 3 matrix of constants given as three rows.
Eigen::Matrix3d Matrix(const FileContext& c, const YAML::Node& node, const std::string& kp,
                       const std::string& what) {
  if (!node.IsSequence() || node.size() != 3) {
    c.in.ThrowValue(node, kp, "three rows [[a, b, c], [d, e, f], [g, h, i]]");
  }
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i) {
    const std::string row = fmt::format("{}[{}]", kp, i);
    if (!node[i].IsSequence() || node[i].size() != 3) c.in.ThrowValue(node[i], row, "a row of 3");
    for (int j = 0; j < 3; ++j) m(i, j) = c.Constant(node[i][j], fmt::format("{}[{}]", row, j), what);
  }
  return m;
}
// A constant angle of more than a turn is almost always degrees written as radians: refused
// with the fix (`30 deg`). Angles are in rad; `deg` after a number converts.
void CheckAngle(const FileContext& c, const YAML::Node& node, const std::string& kp) {
  const Expression e = c.ParseKinematic(node, kp);
  if (e.is_constant() && std::abs(e.constant_value()) > 2.0 * std::numbers::pi + 1e-9) {
    throw ConfigError(fmt::format("{} = '{}': a constant angle of {:g} rad is more than a turn; "
                                  "angles are in rad: if you meant degrees, write `{} deg`",
                                  c.Where(node, kp), node.Scalar(), e.constant_value(),
                                  node.Scalar()));
  }
}

// An inertia about the mass centre must be physical: symmetric, principal moments
// non-negative, each at most the sum of the other two (triangle inequality).
void CheckInertia(const FileContext& c, const YAML::Node& node, const std::string& kp,
                  const Eigen::Matrix3d& I) {
  const double scale = std::max(1e-300, I.cwiseAbs().maxCoeff());
  const double tol = 1e-9 * scale;
  if ((I - I.transpose()).cwiseAbs().maxCoeff() > tol) {
    throw ConfigError(fmt::format("{}: not symmetric; an inertia matrix has I_xy = I_yx, "
                                  "I_xz = I_zx, I_yz = I_zy", c.Where(node, kp)));
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(I);
  const Eigen::Vector3d l = eig.eigenvalues();  // ascending
  if (l(0) < -tol) {
    throw ConfigError(fmt::format("{}: not a physical inertia: a principal moment is negative "
                                  "({:.6g}, {:.6g}, {:.6g} kg·m²); check the signs (products of "
                                  "inertia are entered as I_xy = −∫xy dm)", c.Where(node, kp),
                                  l(0), l(1), l(2)));
  }
  if (l(0) + l(1) < l(2) - tol) {
    throw ConfigError(fmt::format(
        "{}: not a physical inertia: principal moments {:.6g}, {:.6g}, {:.6g} kg·m² break the "
        "triangle inequality (each must be at most the sum of the other two, equality for a "
        "flat body); for a planar model where only I_zz matters, write [I_zz/2, I_zz/2, I_zz] "
        "(a thin disc), which changes nothing in planar motion", c.Where(node, kp), l(0), l(1),
        l(2)));
  }
}
}  // namespace

void ReadKinematicalEquations(FileContext& c, const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return;
  const int n = c.num_coordinates;
  const std::string kp = "kinematical_equations";
  if (!node.IsSequence() || static_cast<int>(node.size()) != n) {
    c.in.ThrowValue(node, kp, fmt::format("the {0} × {0} matrix W(q) of q̇ = W(q) u as {0} rows", n));
  }
  if (c.first_general.empty()) c.first_general = c.Where(node, kp) + " (W(q))";
  auto W = std::make_shared<std::vector<Expression>>();
  for (int i = 0; i < n; ++i) {
    const std::string row = fmt::format("{}[{}]", kp, i);
    if (!node[i].IsSequence() || static_cast<int>(node[i].size()) != n) {
      c.in.ThrowValue(node[i], row, fmt::format("a row of {} expressions", n));
    }
    for (int j = 0; j < n; ++j) W->push_back(c.ParseKinematic(node[i][j], fmt::format("{}[{}]", row, j)));
  }
  c.mirror->W = *W;
  c.builder->SetKinematicalEquations([W](const auto& a, auto out) {
    using J = std::decay_t<decltype(a.t)>;
    const Variables<J> v{a.t, a.q, {}, {}, {}};
    for (std::size_t i = 0; i < W->size(); ++i) out[i] = Evaluate((*W)[i], v);
  });
}

void ReadFrames(FileContext& c, const YAML::Node& root_frames) {
  std::vector<std::string> labels;
  const std::vector<YAML::Node> items = ListItems(c.in, root_frames, "frames", &labels);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const YAML::Node& f = items[i];
    const std::string& kp = labels[i];
    c.in.RequireMapping(f, kp);
    c.in.CheckKeys(f, kp, {"name", "parent", "axis", "angle", "euler", "dcm"});
    const std::string name = c.in.String(f["name"], kp + ".name", "a frame name");
    CheckName(c.in, f["name"], kp + ".name", name);
    if (c.frames.count(name) || c.points.count(name)) {
      throw ConfigError(fmt::format("{} = '{}': already declared; give every frame and point "
                                    "its own name", c.Where(f["name"], kp + ".name"), name));
    }
    const FrameId parent = f["parent"] ? c.Frame(f["parent"], kp + ".parent") : FrameId{0};
    const int mirror_parent = f["parent"] ? c.mirror->frame_ids.at(f["parent"].Scalar()) : 0;
    // Records a rotation about `axis` (in the mirror's parent) for velocity() in loads.
    auto mirror_frame = [&](const std::string& frame_name, int mirror_of, const Eigen::Vector3d& axis,
                            Expression angle) {
      c.mirror->frames.push_back({mirror_of, axis.normalized(), std::move(angle)});
      const int id = static_cast<int>(c.mirror->frames.size()) - 1;
      c.mirror->frame_ids[frame_name] = id;
      return id;
    };
    const std::string where = c.Where(f, kp);
    const int kinds = (f["angle"] ? 1 : 0) + (f["euler"] ? 1 : 0) + (f["dcm"] ? 1 : 0);
    if (kinds != 1) {
      throw ConfigError(fmt::format("{}: give exactly one of `axis` + `angle` (a rotation about "
                                    "an axis), `euler` (a body-fixed sequence) or `dcm` (a "
                                    "constant rotation matrix)", where));
    }
    FrameId id;
    if (f["angle"]) {
      const Eigen::Vector3d axis = f["axis"] ? Axis(c, f["axis"], kp + ".axis")
                                             : Eigen::Vector3d::UnitZ();
      CheckAngle(c, f["angle"], kp + ".angle");
      mirror_frame(name, mirror_parent, axis,
                   c.ParseKinematic(f["angle"], kp + ".angle", kDimensionless));
      multibody::ScalarField angle = c.Field(f["angle"], kp + ".angle", kDimensionless);
      id = AtPlace(where, [&] { return c.builder->AddFrameAboutAxis(name, parent, axis, angle); });
    } else if (f["euler"]) {
      // Body-fixed sequence: each rotation about an axis of the frame turned so far.
      const YAML::Node e = f["euler"];
      c.in.RequireMapping(e, kp + ".euler");
      c.in.CheckKeys(e, kp + ".euler", {"sequence", "angles"});
      const std::string seq = c.in.String(e["sequence"], kp + ".euler.sequence",
                                          "three axes such as ZXZ or XYZ");
      const YAML::Node angles = e["angles"];
      bool ok = seq.size() == 3 && angles.IsSequence() && angles.size() == 3;
      for (char a : seq) ok = ok && std::string("XYZxyz").find(a) != std::string::npos;
      for (std::size_t k = 1; ok && k < 3; ++k) ok = std::toupper(seq[k]) != std::toupper(seq[k - 1]);
      if (!ok) {
        c.in.ThrowValue(e, kp + ".euler", "{sequence: three axes, no two consecutive alike "
                                          "(e.g. ZXZ, XYZ), angles: [a1, a2, a3]}");
      }
      FrameId prev = parent;
      int mirror_prev = mirror_parent;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d axis = Eigen::Vector3d::Unit(std::toupper(seq[k]) - 'X');
        CheckAngle(c, angles[k], fmt::format("{}.euler.angles[{}]", kp, k));
        multibody::ScalarField angle =
            c.Field(angles[k], fmt::format("{}.euler.angles[{}]", kp, k), kDimensionless);
        const std::string part = k == 2 ? name : fmt::format("{}.{}", name, k + 1);
        mirror_prev = mirror_frame(part, mirror_prev, axis,
                                   c.ParseKinematic(angles[k], fmt::format("{}.euler.angles[{}]", kp, k)));
        prev = AtPlace(where, [&] { return c.builder->AddFrameAboutAxis(part, prev, axis, angle); });
      }
      id = prev;
    } else {
      // A constant rotation: checked to be proper orthogonal, then stored as axis and angle.
      const Eigen::Matrix3d R = Matrix(c, f["dcm"], kp + ".dcm", "a direction cosine");
      const double orth = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
      if (!(orth < 1e-9) || !(R.determinant() > 0.0)) {
        throw ConfigError(fmt::format("{}: not a rotation matrix (|RᵀR − I| = {:.3g}, det R = "
                                      "{:.6g}); give an orthonormal matrix with determinant +1 "
                                      "whose columns are the new frame's unit vectors in the "
                                      "parent frame", c.Where(f["dcm"], kp + ".dcm"), orth,
                                      R.determinant()));
      }
      const Eigen::AngleAxisd aa(R);
      mirror_frame(name, mirror_parent, aa.axis(), Expression::Constant(aa.angle()));
      id = AtPlace(where, [&] {
        return c.builder->AddFrameAboutAxis(name, parent, aa.axis(),
                                            multibody::ScalarField::Constant(aa.angle()));
      });
    }
    c.frames[name] = id;
  }
}

void ReadPoints(FileContext& c, const YAML::Node& node) {
  std::vector<std::string> labels;
  const std::vector<YAML::Node> items = ListItems(c.in, node, "points", &labels);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const YAML::Node& p = items[i];
    const std::string& kp = labels[i];
    c.in.RequireMapping(p, kp);
    c.in.CheckKeys(p, kp, {"name", "from", "frame", "position"});
    const std::string name = c.in.String(p["name"], kp + ".name", "a point name");
    CheckName(c.in, p["name"], kp + ".name", name);
    if (c.frames.count(name) || c.points.count(name)) {
      throw ConfigError(fmt::format("{} = '{}': already declared; give every frame and point "
                                    "its own name", c.Where(p["name"], kp + ".name"), name));
    }
    const PointId from = p["from"] ? c.Point(p["from"], kp + ".from") : PointId{0};
    const FrameId frame = p["frame"] ? c.Frame(p["frame"], kp + ".frame") : FrameId{0};
    const YAML::Node pos = c.Require(p, "position", kp, "three components [x, y, z] in `frame`, in m");
    c.RequireVector3(pos, kp + ".position", "three components [x, y, z] in `frame`, in m");
    std::array<multibody::ScalarField, 3> position;
    for (int k = 0; k < 3; ++k) {
      position[k] = c.Field(pos[k], fmt::format("{}.position[{}]", kp, k), kLength);
    }
    Mirror::Point mirror_point;
    mirror_point.from = p["from"] ? c.mirror->point_ids.at(p["from"].Scalar()) : 0;
    mirror_point.frame = p["frame"] ? c.mirror->frame_ids.at(p["frame"].Scalar()) : 0;
    for (int k = 0; k < 3; ++k) {
      mirror_point.position[static_cast<std::size_t>(k)] =
          c.ParseKinematic(pos[k], fmt::format("{}.position[{}]", kp, k));
    }
    c.mirror->points.push_back(std::move(mirror_point));
    c.mirror->point_ids[name] = static_cast<int>(c.mirror->points.size()) - 1;
    c.points[name] = AtPlace(c.Where(p, kp), [&] {
      return c.builder->AddPoint(name, from, frame, std::move(position));
    });
  }
}

void ReadMasses(FileContext& c, const YAML::Node& particles, const YAML::Node& bodies) {
  std::vector<std::string> labels;
  const std::vector<YAML::Node> ps = ListItems(c.in, particles, "particles", &labels);
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const std::string& kp = labels[i];
    c.in.RequireMapping(ps[i], kp);
    c.in.CheckKeys(ps[i], kp, {"name", "point", "mass"});
    const std::string name = c.in.String(ps[i]["name"], kp + ".name", "a name");
    CheckName(c.in, ps[i]["name"], kp + ".name", name, NameKind::kText);
    const PointId point = c.Point(ps[i]["point"], kp + ".point");
    const double mass = c.Constant(c.Require(ps[i], "mass", kp, "a positive mass in kg"),
                                   kp + ".mass", "a positive mass in kg", kMass);
    AtPlace(c.Where(ps[i]["mass"], kp + ".mass"),
            [&] { c.builder->AddParticle(name, point, mass); return 0; });
  }
  std::vector<std::string> body_labels;
  const std::vector<YAML::Node> bs = ListItems(c.in, bodies, "bodies", &body_labels);
  for (std::size_t i = 0; i < bs.size(); ++i) {
    const std::string& kp = body_labels[i];
    c.in.RequireMapping(bs[i], kp);
    c.in.CheckKeys(bs[i], kp, {"name", "frame", "mass_center", "mass", "inertia"});
    const std::string name = c.in.String(bs[i]["name"], kp + ".name", "a name");
    CheckName(c.in, bs[i]["name"], kp + ".name", name, NameKind::kText);
    const FrameId frame = c.Frame(bs[i]["frame"], kp + ".frame");
    const PointId center = c.Point(bs[i]["mass_center"], kp + ".mass_center");
    // Mass and inertia are required: a forgotten `mass:` must not make a body massless.
    const double mass = c.Constant(
        c.Require(bs[i], "mass", kp, "a non-negative mass in kg (write `mass: 0` for none)"),
        kp + ".mass", "a non-negative mass in kg", kMass);
    const YAML::Node in = c.Require(bs[i], "inertia", kp,
                                    "the inertia about the mass centre in `frame`, [Ixx, Iyy, "
                                    "Izz] or three rows, in kg·m² (write [0, 0, 0] for none)");
    Eigen::Matrix3d I;
    if (in.IsSequence() && in.size() > 0 && in[0].IsScalar()) {
      c.RequireVector3(in, kp + ".inertia", "[Ixx, Iyy, Izz] or three rows [[...], [...], [...]]");
      I.setZero();
      for (int k = 0; k < 3; ++k) {
        I(k, k) = c.Constant(in[k], fmt::format("{}.inertia[{}]", kp, k), "a principal moment in kg·m²",
                             kInertia);
      }
    } else {
      I = Matrix(c, in, kp + ".inertia", "an inertia entry in kg·m²");
    }
    CheckInertia(c, in, kp + ".inertia", I);
    AtPlace(c.Where(in, kp + ".inertia"),
            [&] { c.builder->AddRigidBody(name, frame, center, mass, I); return 0; });
  }
}

}  // namespace hybridtest::modelfile::internal
