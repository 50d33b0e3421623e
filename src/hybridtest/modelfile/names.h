#pragma once
// The one rule for names that enter from a model file (issue 45 item 2, docs/model-files.md,
// "Names"). Every name a model file declares can reach generated text: C (compile-model,
// `model: {compiled: true}`), a Python module (equations --format sympy), LaTeX (--format
// latex), Markdown and the run's record. So each is checked here, where the file is read,
// before anything is built or written:
//   - one or more identifiers joined by single dots (`q1`, `theta_dot`, `blade1.k_b`); an
//     identifier is ASCII letters, digits and `_`, not starting with a digit;
//   - at most kMaxNameLength characters;
//   - no part a keyword of C, C++ or Python (`if`, `class`, `import`, `lambda`, ...);
//   - no part starting with `__` or with `_` and a capital letter (reserved in C and C++;
//     Python's dunder names such as __import__);
// The model's `name:` (a label, also a file-name stem of the compiled model) may in addition
// use `-` after its first character (`turbine-damper`).
// The names of loads, particles, bodies and constraints reach no generator (they label the
// engine's loads and the record's columns): they are text, kText: letters, digits, spaces and
// `_ - . , ( ) :` (`gravity on bob 1`), not starting or ending with a space, at most
// kMaxNameLength characters; no keyword check.
// LaTeX has no keywords: a name of these characters can only print as text or a subscript.
// Names that clash with the generated code's own (a Python module's `sp`, `q`, `M`, ...) are
// not refused: the generators rename them (print_expression.h, PythonName). The generators
// escape what they write as well (defence in depth): this rule is the first fence, not the
// only one.
#include <string>
#include <string_view>

#include "hybridtest/common/yaml_input.h"

namespace hybridtest::modelfile {

inline constexpr std::size_t kMaxNameLength = 64;

enum class NameKind {
  kSymbol,  // coordinates, speeds, parameters, frames, points, slots, loads, ...
  kLabel,   // the model's `name:`: may also contain '-'
  kText,    // loads, particles, bodies, constraints: see above
};

// Empty if `name` follows the rule; otherwise the part of the rule it breaks, as a phrase
// ("starts with a digit", "'import' is a keyword of Python", ...).
std::string NameProblem(std::string_view name, NameKind kind = NameKind::kSymbol);

// Throws ConfigError "FILE:LINE: KEY_PATH = 'NAME': not a valid name: PROBLEM; THE RULE; FIX"
// when NameProblem(name, kind) is not empty. `node` is where the name was written (the key
// itself for a mapping's key). The name is shown with control characters escaped.
void CheckName(const YamlInput& in, const YAML::Node& node, std::string_view key_path,
               const std::string& name, NameKind kind = NameKind::kSymbol);

// `stem` (a file name's stem) made to follow the rule for kLabel: other characters become
// '_', a leading digit or '-' gets a '_' before it, and it is cut to kMaxNameLength. The model's
// name when the file has no `name:`.
std::string LabelFromStem(std::string_view stem);

}  // namespace hybridtest::modelfile
