// The intruder as the stages that follow it see it: its outline at one
// snapshot (Intruder), and the pull, its prescribed velocity V (Pull: the frame
// v* = |v - V| / |V| and the spectra's speeds are taken in). Found by its role
// `intruder` in the run file. SI units (m, m/s).
#pragma once

#include <cmath>
#include <cstddef>

#include "common/snapshot_source.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

// The intruder at one snapshot: a horizontal bar's centre, tips and top face
// (its outline's extents, the rounding included).
struct Intruder {
  double xc = 0.0, yc = 0.0;       // centre of its core (m)
  double left = 0.0, right = 0.0;  // x of its tips (ends of the caps)
  double top = 0.0;                // y of its top face
  double length() const { return right - left; }
  Vec2 centre() const { return {xc, yc}; }
};
Intruder intruder_of(const Body& b);

// The pull: the intruder's body index and its prescribed velocity
// (/bodies/velocity) over the whole run.
struct Pull {
  std::size_t body = 0;
  Vec2 velocity;                                                     // V (m/s)
  double speed() const { return std::hypot(velocity.x, velocity.y); }  // |V| (m/s)
};
// The run's pull; an error naming the file if no body has the role `intruder`.
Pull pull_of(const SnapshotSource& run);
Pull pull_of(const RunReader& run);

}  // namespace dem2d::analysis
