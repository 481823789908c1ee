// The simulation state as arrays of plain numbers (structure of arrays).
// A particle's index is its identity for the whole run: it never changes,
// so run-file columns, contact lists and checkpoints all refer to it.
//
// Units: SI, 2D per unit depth. Lengths m, velocities m/s, angles rad,
// masses kg/m (m = rho*pi*d^2/4), moments of inertia kg*m (I = m*d^2/8),
// forces N/m, torques N*m/m = N.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/aligned_vector.hpp"
#include "core/motion.hpp"

namespace dem2d {

struct Particles {
  // kinematics
  AlignedVector<double> x, y;     // centre (m)
  AlignedVector<double> vx, vy;   // velocity (m/s)
  AlignedVector<double> theta;    // orientation (rad), integrated from omega
  AlignedVector<double> omega;    // angular velocity (rad/s), counter-clockwise positive
  // resultant from the last force evaluation
  AlignedVector<double> fx, fy;   // force (N/m)
  AlignedVector<double> torque;   // torque (N)
  // constants
  AlignedVector<double> radius;       // (m)
  AlignedVector<double> mass;         // (kg/m)
  AlignedVector<double> inv_mass;     // (m/kg)
  AlignedVector<double> inv_inertia;  // 1/(kg*m)
  AlignedVector<std::uint8_t> active;  // 0 once a particle has left the domain

  std::size_t size() const { return x.size(); }
  void resize(std::size_t n);
};

// Sphero-lines: a segment from (ax, ay) to (bx, by) with round caps of radius
// `radius` (cap diameter d_s = 2*radius). Static walls have zero velocity;
// kinematic bodies translate either on a schedule (anchor_step < 0:
// C1 = origin + the schedule's displacement at t = step dt, core/motion.hpp)
// or at a constant velocity that may change during a run:
// C1 = anchor + v (step - anchor_step) dt, the anchor being where the body
// was when its velocity last changed (exact, no accumulated round-off). A
// velocity set during the run (a jam's tap) ends a schedule. A removed body (active = 0) no longer
// touches anything. Forces and torques are those the grains exert on the
// body; torque is about the segment middle.
struct Bodies {
  std::vector<std::string> name;
  std::vector<double> ax, ay, bx, by;  // segment end points C1, C2 (m)
  std::vector<double> radius;          // cap radius (m)
  std::vector<double> vx, vy;          // prescribed velocity (m/s)
  std::vector<double> anchor_x, anchor_y;  // C1 when the velocity last changed (m)
  std::vector<std::int64_t> anchor_step;   // step when the velocity last changed; < 0: on its schedule
  std::vector<MotionSchedule> schedule;     // the scene's (empty: none)
  std::vector<double> origin_x, origin_y;   // C1 at t = 0, where a schedule starts (m)
  std::vector<std::uint8_t> active;        // 0 once removed
  std::vector<std::uint8_t> removing;      // 1: removed at the next list rebuild (its contacts
                                           // still act in the current step)
  std::vector<double> fx, fy;          // force from the grains, last step (N/m)
  std::vector<double> torque;          // torque from the grains about the middle (N)

  std::size_t size() const { return name.size(); }
  void resize(std::size_t n);
  double centre_x(std::size_t b) const { return 0.5 * (ax[b] + bx[b]); }
  double centre_y(std::size_t b) const { return 0.5 * (ay[b] + by[b]); }
};

}  // namespace dem2d
