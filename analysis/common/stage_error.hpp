// Bad input for a stage (run file contents, events, config): its command exits 2.
#pragma once

#include <stdexcept>

namespace dem2d::analysis {

struct StageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace dem2d::analysis
