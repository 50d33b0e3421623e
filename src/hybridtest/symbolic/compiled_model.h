#pragma once
// A model compiled to a shared library (issue 36 item 3, decision 0019, docs/equations.md).
//
// CompileModel finds the model's library in the cache, or generates its C (codegen.h) and
// builds it with the system C compiler into the cache; then loads it with dlopen and checks it
// against the numeric engine at kCheckStates random states before returning it. The file name
// holds a hash of the model's sizes, the engine's outputs (their bits) at four fixed states,
// the compiler command and the generator's version: GiNaC orders terms by hashes of addresses,
// so the C text itself differs from process to process, the engine's numbers do not. A cache
// hit derives nothing. The caller attaches the result:
//
//   model.AttachCompiledRhs(symbolic::CompileModel(model, "rotor"));
//
// after which CalcStateDerivative<double> calls it in place of the engine's kinematics, mass
// matrix and forcing, and for a constrained model of its constraint rows (the reduction stays
// the engine's, constraints.h).
//
// The compiler: $CC if set (a program name or path, no arguments), else `cc` on the PATH
// (Debian: gcc, from build-essential). Flags: -O2 -fPIC -shared, and -lm; no -ffast-math, so
// the arithmetic stays IEEE.
// The cache: $HYBRIDTEST_CACHE_DIR if set, else $XDG_CACHE_HOME/hybridtest/compiled-models,
// else $HOME/.cache/hybridtest/compiled-models. Each model leaves NAME-HASH.c (the source),
// NAME-HASH.so, NAME-HASH.sha256 (their digests) and NAME-HASH.lock there; deleting the
// directory is always safe. The cache is private (model_cache.h): created 0700, refused unless
// owned by this user and writable by no one else, and a library is loaded only if its digests
// equal the record written when it was built, checked before dlopen.
#include <filesystem>
#include <memory>
#include <string>

#include "hybridtest/multibody/model.h"
#include "hybridtest/multibody/symbolic_compiled.h"

namespace hybridtest::symbolic {

inline constexpr const char* kCompiledFunction = "hybridtest_rhs";
inline constexpr int kCheckStates = 8;

struct CompileReport {
  std::string library;          // the shared library's path
  bool from_cache = false;      // found in the cache (not compiled now)
  int temporaries = 0;          // common subexpressions in the C
  int operations = 0;           // operations in the C
  double largest_difference = 0.0;  // of the load-time check, relative to each output's size
};

std::filesystem::path CompiledModelCacheDir();

// Throws ModelError if the model cannot be written in C (a table) or the library disagrees
// with the engine, Error if the compiler is missing or fails (its messages in NAME-HASH.log).
std::shared_ptr<const multibody::CompiledRhs> CompileModel(const multibody::Model& model,
                                                            const std::string& model_name,
                                                            CompileReport* report = nullptr);

// Loads a shared library built from WriteC(…, kCompiledFunction) for `model` and checks it:
// before dlopen, its directory, owner, mode and digests (OpenCheckedLibrary); after, its
// (sizes, then M, g, q̇, ż and a constrained model's constraint rows B, B u + c, f(q, t) and
// Ḃ u + ċ at kCheckStates random states within 1e-9 of each output's largest entry; a
// disagreement names the output). Returns the largest relative difference in *difference.
std::shared_ptr<const multibody::CompiledRhs> LoadCompiledModel(const multibody::Model& model,
                                                                const std::string& library,
                                                                double* difference = nullptr);

}  // namespace hybridtest::symbolic
