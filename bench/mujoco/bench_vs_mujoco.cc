// Side by side with MuJoCo (Debian's libmujoco-dev, an optional benchmark dependency; this
// file is built only where CMake finds it): the same tree, built for both engines from one
// description (bench/tree_description.h; the MJCF is generated with nested <body> elements,
// split into <include>d files every 40 levels because tinyxml2 refuses nesting deeper than 100),
// checked to agree on q̈ before timing, and timed in interleaved blocks of thread CPU time.
//
//   VsMujoco/Chain/n    an n-link pendulum, n = 4, 10, 30, 100
//   VsMujoco/RotorTree  a tower, a hub and three blades of 10 bodies (n = 32)
//
// Counters: kane_us and mujoco_us (per call: CalcStateDerivative<double> against mj_forward
// on the same state) and ratio = kane_us / mujoco_us, all from the same rounds.
#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include <stdlib.h>

#include <cstdio>
#include <ctime>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>

#include "hybridtest/multibody/kane.h"
#include "tree_description.h"

namespace hybridtest::bench {
namespace {

std::string Vec(const Eigen::Vector3d& v) {
  char s[128];
  std::snprintf(s, sizeof s, "%.17g %.17g %.17g", v(0), v(1), v(2));
  return s;
}

// tinyxml2 refuses elements nested deeper than 100; a chain of 100 bodies is deeper. Every
// kSplitDepth levels the subtree goes to its own file, pulled in with <include> (MuJoCo
// copies an included file's children in place, after parsing it on its own).
constexpr int kSplitDepth = 40;

struct MjcfFiles {
  std::string dir;
  std::vector<std::string> paths;  // written, removed after loading
};

void WriteBody(const std::vector<BodyDescription>& bodies, int i, int depth, MjcfFiles& files,
               std::string& xml) {
  if (depth > 0 && depth % kSplitDepth == 0) {
    std::string sub = "<mujoco>\n";
    WriteBody(bodies, i, depth + 1, files, sub);
    sub += "</mujoco>\n";
    const std::string name = "part" + std::to_string(files.paths.size()) + ".xml";
    std::ofstream(files.dir + "/" + name) << sub;
    files.paths.push_back(files.dir + "/" + name);
    xml += "<include file=\"" + name + "\"/>\n";
    return;
  }
  const BodyDescription& d = bodies[i];
  xml += "<body pos=\"" + Vec(d.offset) + "\">";
  xml += std::string("<joint type=\"") + (d.hinge ? "hinge" : "slide") + "\" axis=\"" +
         Vec(d.axis) + "\"/>";
  char mass[64];
  std::snprintf(mass, sizeof mass, "%.17g", d.mass);
  xml += "<inertial pos=\"" + Vec(d.com) + "\" mass=\"" + mass + "\" diaginertia=\"" +
         Vec(d.inertia) + "\"/>";
  for (std::size_t c = 0; c < bodies.size(); ++c) {
    if (bodies[c].parent == i) WriteBody(bodies, static_cast<int>(c), depth + 1, files, xml);
  }
  xml += "</body>\n";
}

mjModel* BuildMujocoModel(const std::vector<BodyDescription>& bodies) {
  MjcfFiles files;
  char dir_template[] = "/tmp/hybridtest_vs_mujoco_XXXXXX";
  if (mkdtemp(dir_template) == nullptr) throw std::runtime_error("cannot create a temporary directory");
  files.dir = dir_template;
  std::string xml =
      "<mujoco><compiler angle=\"radian\" inertiafromgeom=\"false\"/>"
      "<option timestep=\"0.001\" gravity=\"0 0 " + std::to_string(-kGravity) + "\">"
      "<flag contact=\"disable\"/></option><worldbody>\n";
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].parent < 0) WriteBody(bodies, static_cast<int>(i), 0, files, xml);
  }
  xml += "</worldbody></mujoco>\n";
  const std::string path = files.dir + "/model.xml";
  std::ofstream(path) << xml;
  files.paths.push_back(path);
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  for (const auto& p : files.paths) std::remove(p.c_str());
  std::remove(files.dir.c_str());
  if (m == nullptr) throw std::runtime_error(std::string("MuJoCo: ") + error);
  return m;
}

double ThreadSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void RunSideBySide(benchmark::State& state, const std::vector<BodyDescription>& bodies) {
  const multibody::Model model = BuildKaneModel(bodies);
  const int n = model.num_coordinates();
  multibody::Data<double> data(model);
  mjModel* m = BuildMujocoModel(bodies);
  mjData* d = mj_makeData(m);
  if (m->nq != n || m->nv != n) {
    state.SkipWithError("MuJoCo model has a different number of coordinates");
    return;
  }
  // States, and the agreement check on q̈.
  constexpr int kStates = 16;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Eigen::VectorXd> xs;
  const Eigen::VectorXd r = Eigen::VectorXd::Zero(0);
  Eigen::VectorXd xdot(2 * n);
  double worst = 0.0;
  for (int s = 0; s < kStates; ++s) {
    Eigen::VectorXd x(2 * n);
    for (int i = 0; i < 2 * n; ++i) x(i) = (i < n ? 0.5 : 1.0) * unit(rng);
    xs.push_back(x);
    multibody::CalcStateDerivative<double>(model, data, 0.0, x, r, xdot);
    for (int i = 0; i < n; ++i) {
      d->qpos[i] = x(i);
      d->qvel[i] = x(n + i);
    }
    mj_forward(m, d);
    double scale = 1.0;
    for (int i = 0; i < n; ++i) scale = std::max(scale, std::abs(d->qacc[i]));
    for (int i = 0; i < n; ++i) worst = std::max(worst, std::abs(d->qacc[i] - xdot(n + i)) / scale);
  }
  if (!(worst < 1e-8)) {
    state.SkipWithError(("q̈ differs from MuJoCo's by " + std::to_string(worst)).c_str());
    mj_deleteData(d);
    mj_deleteModel(m);
    return;
  }
  // Interleaved blocks of thread CPU time.
  const int block = std::max(4, 4000 / (n * n / 4 + 8));
  double kane = 0.0, mujoco = 0.0;
  long calls = 0;
  int s = 0;
  for (auto _ : state) {
    double t0 = ThreadSeconds();
    for (int k = 0; k < block; ++k) {
      const Eigen::VectorXd& x = xs[(s + k) % kStates];
      multibody::CalcStateDerivative<double>(model, data, 0.0, x, r, xdot);
      benchmark::DoNotOptimize(xdot.data());
    }
    double t1 = ThreadSeconds();
    kane += t1 - t0;
    for (int k = 0; k < block; ++k) {
      const Eigen::VectorXd& x = xs[(s + k) % kStates];
      for (int i = 0; i < n; ++i) {
        d->qpos[i] = x(i);
        d->qvel[i] = x(n + i);
      }
      mj_forward(m, d);
      benchmark::DoNotOptimize(d->qacc);
    }
    mujoco += ThreadSeconds() - t1;
    calls += block;
    s = (s + block) % kStates;
  }
  state.counters["n"] = n;
  state.counters["kane_us"] = 1e6 * kane / static_cast<double>(calls);
  state.counters["mujoco_us"] = 1e6 * mujoco / static_cast<double>(calls);
  state.counters["ratio"] = kane / mujoco;
  state.counters["qdd_rel_diff"] = worst;
  state.SetLabel(model.tree_mass_matrix() ? "tree mass matrix" : "pairwise mass matrix");
  mj_deleteData(d);
  mj_deleteModel(m);
}

void BM_VsMujocoChain(benchmark::State& state) {
  RunSideBySide(state, ChainDescription(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_VsMujocoChain)->Name("VsMujoco/Chain")->Arg(4)->Arg(10)->Arg(30)->Arg(100)
    ->MinTime(0.5);

void BM_VsMujocoRotorTree(benchmark::State& state) { RunSideBySide(state, RotorTreeDescription(10)); }
BENCHMARK(BM_VsMujocoRotorTree)->Name("VsMujoco/RotorTree")->MinTime(0.5);

}  // namespace
}  // namespace hybridtest::bench
