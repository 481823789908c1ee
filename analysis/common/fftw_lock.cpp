#include "common/fftw_lock.hpp"

namespace dem2d::analysis {

std::mutex& fftw_planner_lock() {
  static std::mutex m;
  return m;
}

}  // namespace dem2d::analysis
