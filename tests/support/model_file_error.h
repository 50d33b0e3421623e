#pragma once
// The ConfigError a model file's text gives when it is parsed and built (as "m.yaml"), or
// "no error". For the model-file tests that assert messages.
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/model_file.h"

namespace test_support {

inline std::string ModelFileError(const std::string& text) {
  using namespace hybridtest;
  try {
    const modelfile::ModelFile f = modelfile::ParseModelFile(YamlInput::FromText(text, "m.yaml"));
    modelfile::BuildModelFile(f, f.parameters);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace test_support
