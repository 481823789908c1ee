// Constants every stage shares: the unit its metrics are written in and the
// value of a measurement that could not be made.
#pragma once

#include <limits>

namespace dem2d::analysis {

inline constexpr double kMm = 1e3;  // m -> mm
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace dem2d::analysis
