// The name rule of model files. See names.h.
#include "hybridtest/modelfile/names.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <set>

#include "hybridtest/common/error.h"
#include "hybridtest/common/text.h"

namespace hybridtest::modelfile {

namespace {

// The keywords of C (C23), C++ (C++23) and Python (3.12, hard keywords), the languages the
// generators write. Reserved forms (`__x`, `_X`) are refused by their shape instead.
const std::set<std::string, std::less<>>& Keywords() {
  static const std::set<std::string, std::less<>> kWords = {
      // C
      "alignas", "alignof", "auto", "bool", "break", "case", "char", "const", "constexpr",
      "continue", "default", "do", "double", "else", "enum", "extern", "false", "float", "for",
      "goto", "if", "inline", "int", "long", "nullptr", "register", "restrict", "return",
      "short", "signed", "sizeof", "static", "static_assert", "struct", "switch",
      "thread_local", "true", "typedef", "typeof", "typeof_unqual", "union", "unsigned", "void",
      "volatile", "while",
      // C++ (beyond C)
      "and", "and_eq", "asm", "bitand", "bitor", "catch", "char8_t", "char16_t", "char32_t",
      "class", "co_await", "co_return", "co_yield", "compl", "concept", "const_cast",
      "consteval", "constinit", "decltype", "delete", "dynamic_cast", "explicit", "export",
      "friend", "mutable", "namespace", "new", "noexcept", "not", "not_eq", "operator", "or",
      "or_eq", "private", "protected", "public", "reinterpret_cast", "requires", "static_cast",
      "template", "this", "throw", "try", "typeid", "typename", "using", "virtual", "wchar_t",
      "xor", "xor_eq",
      // Python (beyond the above)
      "False", "None", "True", "as", "assert", "async", "await", "def", "del", "elif",
      "except", "finally", "from", "global", "import", "in", "is", "lambda", "nonlocal",
      "pass", "raise", "with", "yield"};
  return kWords;
}

std::string Language(std::string_view word) {
  static const std::set<std::string_view> kPythonOnly = {
      "False", "None", "True", "as", "assert", "async", "await", "def", "del", "elif", "except",
      "finally", "from", "global", "import", "in", "is", "lambda", "nonlocal", "pass", "raise",
      "with", "yield"};
  return kPythonOnly.count(word) > 0 ? "Python" : "C, C++ or Python";
}

// The problem of one dot-separated part, or empty.
std::string PartProblem(std::string_view part, NameKind kind) {
  if (part.empty()) return "has an empty part (a dot at its start or end, or two dots)";
  if (std::isdigit(static_cast<unsigned char>(part[0]))) return "starts with a digit";
  for (char ch : part) {
    const auto u = static_cast<unsigned char>(ch);
    const bool ok = std::isalnum(u) || ch == '_' || (kind == NameKind::kLabel && ch == '-');
    if (u >= 0x80) return "has a character that is not ASCII";
    if (!ok) {
      if (std::isprint(u)) return fmt::format("has the character '{}'", ch);
      return fmt::format("has the control character \\x{:02x}", static_cast<unsigned>(u));
    }
  }
  if (part[0] == '-') return "starts with '-'";
  if (part.size() >= 2 && part[0] == '_' &&
      (part[1] == '_' || std::isupper(static_cast<unsigned char>(part[1])))) {
    return fmt::format("'{}' starts with '__' or '_' and a capital letter (reserved in C and "
                       "C++, and Python's special names)", part);
  }
  if (Keywords().count(part) > 0) {
    return fmt::format("'{}' is a keyword of {}", part, Language(part));
  }
  return {};
}

// The problem of a kText name, or empty.
std::string TextProblem(std::string_view name) {
  for (char ch : name) {
    const auto u = static_cast<unsigned char>(ch);
    if (u >= 0x80) return "has a character that is not ASCII";
    if (std::isalnum(u) || std::string_view(" _-.,():").find(ch) != std::string_view::npos) {
      continue;
    }
    if (std::isprint(u)) return fmt::format("has the character '{}'", ch);
    return fmt::format("has the control character \\x{:02x}", static_cast<unsigned>(u));
  }
  if (name.front() == ' ' || name.back() == ' ') return "starts or ends with a space";
  return {};
}

}  // namespace

std::string NameProblem(std::string_view name, NameKind kind) {
  if (name.empty()) return "is empty";
  if (name.size() > kMaxNameLength) {
    return fmt::format("is {} characters long (at most {})", name.size(), kMaxNameLength);
  }
  if (kind == NameKind::kText) return TextProblem(name);
  std::size_t begin = 0;
  for (;;) {
    const std::size_t dot = name.find('.', begin);
    const std::string_view part =
        name.substr(begin, dot == std::string_view::npos ? std::string_view::npos : dot - begin);
    if (std::string problem = PartProblem(part, kind); !problem.empty()) return problem;
    if (dot == std::string_view::npos) return {};
    begin = dot + 1;
  }
}

void CheckName(const YamlInput& in, const YAML::Node& node, std::string_view key_path,
               const std::string& name, NameKind kind) {
  const std::string problem = NameProblem(name, kind);
  if (problem.empty()) return;
  // (fmt, not name.substr(0, 60) + "...": GCC 12 flags that concatenation with an -Warray-bounds
  // false positive inside <bits/char_traits.h> once it is inlined here.)
  const std::string shown = Printable(
      name.size() > 80 ? fmt::format("{}...", std::string_view(name).substr(0, 60)) : name);
  std::string suggestion = LabelFromStem(name);
  if (kind == NameKind::kSymbol) std::replace(suggestion.begin(), suggestion.end(), '-', '_');
  if (kind == NameKind::kText) {
    throw ConfigError(fmt::format(
        "{} = '{}': not a valid name: it {}; this name is text of ASCII letters, digits, spaces "
        "and _ - . , ( ) : at most {} characters (docs/model-files.md, \"Names\"); rename it",
        in.Where(node, Printable(key_path)), shown, problem, kMaxNameLength));
  }
  throw ConfigError(fmt::format(
      "{} = '{}': not a valid name: it {}; a name is ASCII letters, digits and '_'{}, not "
      "starting with a digit, at most {} characters, optionally dotted (blade1.k_b), and not a "
      "keyword of C, C++ or Python (names reach generated C, Python and LaTeX; "
      "docs/model-files.md, \"Names\"); rename it, e.g. to '{}'",
      in.Where(node, Printable(key_path)), shown, problem, kind == NameKind::kLabel ? " or '-'" : "",
      kMaxNameLength, suggestion));
}

std::string LabelFromStem(std::string_view stem) {
  std::string s;
  for (char ch : stem.substr(0, kMaxNameLength - 6)) {
    const auto u = static_cast<unsigned char>(ch);
    s += u < 0x80 && (std::isalnum(u) || ch == '_' || ch == '-') ? ch : '_';
  }
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0])) || s[0] == '-') s = "_" + s;
  if (!NameProblem(s, NameKind::kLabel).empty()) s += "_";  // a keyword
  if (!NameProblem(s, NameKind::kLabel).empty()) s = "m" + s;  // a reserved form
  if (!NameProblem(s, NameKind::kLabel).empty()) s = "model";
  return s;
}

}  // namespace hybridtest::modelfile
