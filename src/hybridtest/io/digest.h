#pragma once
// SHA-256 digests: in common/digest.h (the compiled-model cache, below io, uses them too).
#include "hybridtest/common/digest.h"

namespace hybridtest::io {

using hybridtest::Sha256Hex;
using hybridtest::Sha256OfFile;

}  // namespace hybridtest::io
