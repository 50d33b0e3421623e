// Compiling, caching, loading and checking a model's C. See compiled_model.h.
#include "hybridtest/symbolic/compiled_model.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <fmt/core.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/symbolic/codegen.h"
#include "hybridtest/symbolic/model_cache.h"

extern char** environ;

namespace hybridtest::symbolic {

namespace fs = std::filesystem;

namespace {

std::string Env(const char* name) {
  const char* v = std::getenv(name);
  return v == nullptr ? std::string() : std::string(v);
}

std::uint64_t Fnv1a(const std::string& text) {
  std::uint64_t h = 14695981039346656037ULL;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  return h;
}

// A file-name stem from a model's name: letters, digits, '-' and '_' only.
std::string Stem(const std::string& model_name) {
  std::string s;
  for (char c : model_name) s += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
  return s.empty() ? "model" : s;
}

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs argv (argv[0] looked up on the PATH) with its standard error (and output) in `log`.
// Returns the exit status, or −1 if it could not start.
int Run(const std::vector<std::string>& argv, const fs::path& log) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

template <typename Sym>
Sym Symbol(void* library, const std::string& name, const std::string& path) {
  dlerror();
  void* p = dlsym(library, name.c_str());
  if (p == nullptr) {
    throw ModelError(fmt::format("{}: no symbol '{}': not a library that hybridtest compiled "
                                 "for a model; delete it and compile again", path, name));
  }
  return reinterpret_cast<Sym>(p);
}

// The largest |a − b| over the entries, relative to the largest |b| (at least 1).
double Difference(const double* a, const double* b, int size) {
  double scale = 1.0, diff = 0.0;
  for (int i = 0; i < size; ++i) scale = std::max(scale, std::abs(b[i]));
  for (int i = 0; i < size; ++i) diff = std::max(diff, std::abs(a[i] - b[i]));
  return diff / scale;
}

// The outputs of a compiled model, in the order EngineOutputs and CompiledOutputs write them:
// M (column-major), g, q̇, ż and, for a constrained model, B (column-major), B u + c, f(q, t)
// and the bias Ḃ u + ċ.
struct OutputPart {
  const char* name;
  int size;
};
std::vector<OutputPart> OutputParts(const multibody::Model& model) {
  const int n = model.num_coordinates(), nz = model.num_extra_states();
  const int m = model.num_constraint_rows();
  std::vector<OutputPart> parts = {{"M", n * n}, {"g", n}, {"qdot", n}, {"zdot", nz}};
  if (m > 0) {
    parts.insert(parts.end(), {{"the constraint rows B", m * n},
                               {"the constraint velocities B u + c", m},
                               {"the constraint positions f(q, t)", m},
                               {"the constraint bias Bdot u + cdot", m}});
  }
  return parts;
}

int PartsSize(const std::vector<OutputPart>& parts) {
  int size = 0;
  for (const OutputPart& p : parts) size += p.size;
  return size;
}

// The engine's outputs (Parts) at (t, x, r), written to `out`.
void EngineOutputs(const multibody::Model& model, multibody::Data<double>& data, double t,
                   const Eigen::VectorXd& x, const Eigen::VectorXd& r, Eigen::VectorXd& out) {
  const int n = model.num_coordinates(), nz = model.num_extra_states();
  const int m = model.num_constraint_rows();
  multibody::CalcKinematics<double>(model, data, t, x);
  multibody::CalcMassMatrixPairwise<double>(model, data);
  multibody::CalcForcing<double>(model, data, r);
  out.resize(PartsSize(OutputParts(model)));
  out.head(n * n) = data.M.reshaped();
  out.segment(n * n, n) = data.g;
  out.segment(n * n + n, n) = data.qdot;
  const multibody::LoadArgs<double> args{
      t, std::span<const double>(x.data(), n), std::span<const double>(x.data() + n, n), {},
      std::span<const double>(data.time_values.data(), data.time_values.size()),
      std::span<const double>(x.data() + 2 * n, nz)};
  for (int k = 0; k < nz; ++k) {
    out(n * n + 2 * n + k) = model.extra_states()[k].rate.get<double>()(args);
  }
  if (m == 0) return;
  multibody::CalcConstraints<double>(model, data);
  const int at = n * n + 2 * n + nz;
  out.segment(at, m * n) = data.constraint_B.reshaped();
  out.segment(at + m * n, m) = data.constraint_velocity;
  out.segment(at + m * n + m, m) = data.constraint_position;
  out.segment(at + m * n + 2 * m, m) = data.constraint_bias;
}

// The compiled model's outputs (Parts) at (t, x, r), written to `out`.
void CompiledOutputs(const multibody::Model& model, const multibody::CompiledRhs& rhs, double t,
                     const Eigen::VectorXd& x, const Eigen::VectorXd& r, Eigen::VectorXd& out) {
  const int n = model.num_coordinates(), nz = model.num_extra_states();
  const int m = model.num_constraint_rows();
  out.resize(PartsSize(OutputParts(model)));
  double* o = out.data();
  rhs.function(t, x.data(), r.data(), o, o + n * n, o + n * n + n, o + n * n + 2 * n);
  if (m == 0) return;
  double* c = o + n * n + 2 * n + nz;
  rhs.constraints(t, x.data(), c, c + m * n, c + m * n + m, c + m * n + 2 * m);
}

// A random state (t, x, r) of the load-time check and the fingerprint.
double RandomState(std::mt19937& rng, int n, Eigen::VectorXd& x, Eigen::VectorXd& r) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = (i < n ? 1.0 : 3.0) * unit(rng);
  for (Eigen::Index i = 0; i < r.size(); ++i) r(i) = 1000.0 * unit(rng);
  return 5.0 * (1.0 + unit(rng));
}

// The cache key of a model: its sizes and the bits of the engine's outputs at four fixed
// states (GiNaC orders terms by hashes of addresses, so the C text differs from process to
// process; the engine's numbers do not), with the compiler command and kGenerator.
std::uint64_t Fingerprint(const multibody::Model& model, const std::string& command) {
  constexpr const char* kGenerator = "hybridtest codegen 2";  // 2: constraint rows
  std::string key = fmt::format("{}\n{}\n{} {} {} {}\n", kGenerator, command,
                                model.num_coordinates(), model.num_slots(),
                                model.num_extra_states(), model.num_constraint_rows());
  std::mt19937 rng(20261127);
  multibody::Data<double> data(model);
  Eigen::VectorXd x(model.num_states()), r(model.num_slots()), out;
  for (int trial = 0; trial < 4; ++trial) {
    const double t = RandomState(rng, model.num_coordinates(), x, r);
    EngineOutputs(model, data, t, x, r, out);
    key.append(reinterpret_cast<const char*>(out.data()), sizeof(double) * out.size());
  }
  return Fnv1a(key);
}

// "N common subexpressions,\n * M operations" from a generated file's header.
void ReadCounts(const fs::path& source, CompileReport& report) {
  const std::string text = ReadAll(source);
  const std::size_t at = text.find("extra states; ");
  if (at == std::string::npos) return;
  std::sscanf(text.c_str() + at + 14, "%d common subexpressions,\n * %d operations",
              &report.temporaries, &report.operations);
}

}  // namespace

fs::path CompiledModelCacheDir() {
  if (const std::string dir = Env("HYBRIDTEST_CACHE_DIR"); !dir.empty()) return dir;
  if (const std::string xdg = Env("XDG_CACHE_HOME"); !xdg.empty()) {
    return fs::path(xdg) / "hybridtest" / "compiled-models";
  }
  const std::string home = Env("HOME");
  if (home.empty()) {
    throw Error("cannot find a cache for compiled models: HOME is not set; set "
                "HYBRIDTEST_CACHE_DIR to a writable directory");
  }
  return fs::path(home) / ".cache" / "hybridtest" / "compiled-models";
}

std::shared_ptr<const multibody::CompiledRhs> CompileModel(const multibody::Model& model,
                                                            const std::string& model_name,
                                                            CompileReport* report) {
  std::string compiler = Env("CC");
  if (compiler.empty()) compiler = "cc";
  const std::vector<std::string> flags = {"-O2", "-fPIC", "-shared"};
  std::string command = compiler;
  for (const std::string& f : flags) command += " " + f;
  const fs::path dir = CompiledModelCacheDir();
  PreparePrivateDir(dir);
  std::error_code ec;
  const std::string stem = fmt::format("{}-{:016x}", Stem(model_name), Fingerprint(model, command));
  const fs::path library = dir / (stem + ".so");
  CompileReport local;
  CompileReport& rep = report != nullptr ? *report : local;
  rep.library = library.string();
  std::optional<CacheLock> lock;
  lock.emplace(library, true);  // one process builds it; none checks it meanwhile
  // A library without its digest record (an older hybridtest's cache, or a build that stopped
  // between its renames) is built again over it, never loaded.
  rep.from_cache = fs::exists(library, ec) && fs::exists(RecordOf(library), ec);
  if (rep.from_cache) {
    ReadCounts(dir / (stem + ".c"), rep);
  } else {
    const CCode code = WriteC(model, DeriveRhs(model), model_name, kCompiledFunction);
    rep.temporaries = code.temporaries;
    rep.operations = code.operations;
    // Written and built under this process's own names, then renamed: another process
    // compiling the same model at the same time never sees a half-written library.
    const std::string own = fmt::format("{}.{}", stem, getpid());
    const fs::path source = dir / (own + ".c"), built = dir / (own + ".so"),
                   log = dir / (own + ".log"), record = dir / (own + ".sha256");
    {
      std::ofstream os(source, std::ios::trunc);
      os << code.source;
      if (!os) throw Error(fmt::format("cannot write {}", source.string()));
    }
    std::vector<std::string> argv = {compiler};
    argv.insert(argv.end(), flags.begin(), flags.end());
    argv.insert(argv.end(), {"-o", built.string(), source.string(), "-lm"});
    const int status = Run(argv, log);
    const std::string messages = status > 0 ? ReadAll(log) : std::string();
    fs::remove(log, ec);
    if (status != 0) {
      fs::remove(source, ec);
      fs::remove(built, ec);
      throw Error(fmt::format(
          "cannot compile model '{}' with the C compiler '{}' ({}): {}; install a C compiler "
          "(Debian: build-essential) or set CC to one", model_name, compiler,
          status < 0 ? "it did not start" : fmt::format("exit status {}", status),
          status < 0 ? "not found on the PATH" : messages));
    }
    // Private whatever the umask (the loader refuses a file others may write), and the
    // digests recorded beside it: the loader compares them before dlopen.
    fs::permissions(source, fs::perms::owner_read | fs::perms::owner_write, ec);
    fs::permissions(built, fs::perms::owner_all, ec);
    WriteDigestRecord(built, source, record);
    fs::rename(record, RecordOf(library), ec);
    if (!ec) fs::rename(source, SourceOf(library), ec);
    if (!ec) fs::rename(built, library, ec);
    if (ec) throw Error(fmt::format("cannot move {} into the cache: {}", built.string(), ec.message()));
  }
  lock.reset();
  return LoadCompiledModel(model, library.string(), &rep.largest_difference);
}

std::shared_ptr<const multibody::CompiledRhs> LoadCompiledModel(const multibody::Model& model,
                                                                const std::string& library,
                                                                double* difference) {
  // Checked (private, digests as recorded) on an open descriptor and loaded from it: the
  // library's constructors run at dlopen, so nothing foreign may get that far.
  const fs::path path(library);
  PreparePrivateDir(path.parent_path().empty() ? fs::path(".") : path.parent_path());
  int fd = -1;
  {
    CacheLock lock(path, false);
    fd = OpenCheckedLibrary(path);
  }
  void* handle = dlopen(fmt::format("/proc/self/fd/{}", fd).c_str(), RTLD_NOW | RTLD_LOCAL);
  ::close(fd);
  if (handle == nullptr) {
    throw ModelError(fmt::format("cannot load the compiled model {}: {}", library, dlerror()));
  }
  auto rhs = std::make_shared<multibody::CompiledRhs>();
  rhs->library = std::shared_ptr<void>(handle, [](void* h) { dlclose(h); });
  rhs->path = library;
  const std::string f = kCompiledFunction;
  rhs->function = Symbol<multibody::CompiledRhsFunction>(handle, f, library);
  const int n = *Symbol<const int*>(handle, f + "_n", library);
  const int slots = *Symbol<const int*>(handle, f + "_slots", library);
  const int nz = *Symbol<const int*>(handle, f + "_nz", library);
  const int m = *Symbol<const int*>(handle, f + "_m", library);
  if (n != model.num_coordinates() || slots != model.num_slots() ||
      nz != model.num_extra_states() || m != model.num_constraint_rows()) {
    throw ModelError(fmt::format("the compiled model {} has n = {}, {} slots, {} extra states, "
                                 "{} constraint rows; the model has {}, {}, {}, {}: it was "
                                 "compiled for another model",
                                 library, n, slots, nz, m, model.num_coordinates(),
                                 model.num_slots(), model.num_extra_states(),
                                 model.num_constraint_rows()));
  }
  if (m > 0) {
    rhs->constraints =
        Symbol<multibody::CompiledConstraintsFunction>(handle, f + "_constraints", library);
  }
  // The load-time check: the engine (its kinematics, pairwise M, forcing and constraint rows)
  // at random states, output by output.
  const std::vector<OutputPart> parts = OutputParts(model);
  std::mt19937 rng(36);
  multibody::Data<double> data(model);
  Eigen::VectorXd x(model.num_states()), r(slots), engine, mine;
  double worst = 0.0;
  for (int trial = 0; trial < kCheckStates; ++trial) {
    const double t = RandomState(rng, n, x, r);
    CompiledOutputs(model, *rhs, t, x, r, mine);
    EngineOutputs(model, data, t, x, r, engine);
    int at = 0;
    for (const OutputPart& part : parts) {
      const double d = Difference(mine.data() + at, engine.data() + at, part.size);
      at += part.size;
      worst = std::max(worst, d);
      if (!(d <= 1e-9)) {
        throw ModelError(fmt::format(
            "the compiled model {} disagrees with the numeric engine in {} at t = {} s "
            "(relative difference {:.3g} > 1e-9): it is stale or was compiled for another "
            "model; delete it and compile again", library, part.name, t, d));
      }
    }
  }
  if (difference != nullptr) *difference = worst;
  return rhs;
}

}  // namespace hybridtest::symbolic
