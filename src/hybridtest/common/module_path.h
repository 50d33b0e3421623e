#pragma once
// FindModule: where a shared object that hybridtest loads or ships at run time lives (the FMU
// binary hybridtest_fmu.so that export-fmu copies, the HDF5 writer hybridtest_hdf5.so that
// report::ExportHdf5 dlopens). One rule for every such module:
//   1. the environment variable `env_override`, when it is set and not empty: that file, as is
//      (not checked: whoever opens it reports a missing file with its name);
//   2. beside the running program (/proc/self/exe): the build tree, where the modules are
//      built beside the hybridtest binary (build/<preset>/apps/hybridtest/);
//   3. <program's directory>/../<libdir>/hybridtest/: an installed hybridtest, relocated or not;
//   4. <install prefix>/<libdir>/hybridtest/, the prefix the tree was configured with: a
//      program of its own linking the installed library;
//   5. the build tree's build/<preset>/apps/hybridtest/: the test executables and the Python
//      module of that tree (tests/, python/), which live elsewhere in it. Only for code that is
//      itself a file of that build tree (dladdr): a library installed from it and linked into
//      another program does not load code from a build directory that may be gone or
//      re-created by someone else.
// Candidates 2-5 count only when the file exists there.
#include <filesystem>
#include <optional>
#include <string>

namespace hybridtest {

struct ModuleLookup {
  std::optional<std::filesystem::path> found;  // the module's file, when one was found
  std::string searched;  // the files looked for, in order, ", "-separated (for an error message)
};

ModuleLookup FindModule(const std::string& file_name, const char* env_override);

}  // namespace hybridtest
