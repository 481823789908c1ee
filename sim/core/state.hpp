// The simulation state as arrays of plain numbers (structure of arrays).
// A particle's index is its identity for the whole run: it never changes,
// so run-file columns, contact lists and checkpoints all refer to it.
//
// Units: SI, 2D per unit depth. Lengths m, velocities m/s, angles rad,
// masses kg/m (m = rho*pi*d^2/4), moments of inertia kg*m (I = m*d^2/8),
// forces N/m, torques N*m/m = N.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/aligned_vector.hpp"
#include "core/motion.hpp"
#include "shape/shape.hpp"

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

// Bodies: convex sphero-polygons (shape/shape.hpp), i.e. a core outline
// (a point, a segment as in the paper, or a polygon) rounded by `radius`. Vertex 0
// of the core is the body's reference point C1. Static walls have zero
// velocity; kinematic bodies move either on a schedule (anchor_step < 0:
// core/motion.hpp), or at a constant velocity that may change during a run:
// C1 = anchor + v (step - anchor_step) dt, the anchor being where the body
// was when its velocity last changed (exact, no accumulated round-off). On a
// schedule that does not turn, C1 = origin + the schedule's displacement at
// t = step dt; one that turns moves the pivot by the displacement and turns
// the outline about it by the schedule's angle (System::place_bodies). A
// velocity set during the run (a jam's tap) ends a schedule; the body keeps
// the angle it had. A removed body (active = 0) no longer touches anything.
// Forces and torques are those the grains exert on the body; torque is about
// the pivot: the scene's, or the mean of the core's vertices (a segment's middle).
struct Bodies {
  std::vector<std::string> name;
  std::vector<std::string> role;       // core/body_roles.hpp ("" none)
  std::vector<std::string> kind;       // the scene's shape kind (shape/shape_kinds.hpp)
  std::vector<Shape> shape;            // core outline at the current step
  std::vector<Segment> line;           // shape[b].edge[0], contiguous: the vectorised sphero-line
                                       // loop reads it (gathers from the large Shapes do not vectorise)
  std::vector<double> centre_x, centre_y;  // mean of the core's vertices (m), kept by set_shape and move_to
  std::vector<double> radius;          // rounding radius (m): half the scene's thickness
  std::vector<double> vx, vy;          // prescribed velocity (m/s); of the pivot for a turning body
  std::vector<double> omega;           // angular velocity about the pivot (rad/s), over the last step
  std::vector<double> angle;           // turned since the start (rad, counter-clockwise)
  std::vector<double> pivot_x, pivot_y;    // the pivot now (m): the centre unless own_pivot
  std::vector<double> pivot0_x, pivot0_y;  // the scene's pivot at t = 0 (m)
  std::vector<std::uint8_t> own_pivot;     // 1: the scene gave a pivot
  std::vector<double> anchor_x, anchor_y;  // C1 when the velocity last changed (m)
  std::vector<std::int64_t> anchor_step;   // step when the velocity last changed; < 0: on its schedule
  std::vector<MotionSchedule> schedule;     // the scene's (empty: none)
  std::vector<double> origin_x, origin_y;   // C1 at t = 0, where a schedule starts (m)
  std::vector<std::uint8_t> active;        // 0 once removed
  std::vector<std::uint8_t> removing;      // 1: removed at the next list rebuild (its contacts
                                           // still act in the current step)
  std::vector<double> fx, fy;          // force from the grains, last step (N/m)
  std::vector<double> torque;          // torque from the grains about the centre (N)

  std::size_t size() const { return name.size(); }
  void resize(std::size_t n);
  void set_shape(std::size_t b, const Shape& s);
  void move_to(std::size_t b, double x, double y);  // vertex 0 to (x, y) (m), turned by angle[b]
  // The body's velocity at the point (x, y) (m/s): its pivot's plus omega x (point - pivot).
  std::array<double, 2> velocity_at(std::size_t b, double x, double y) const;

 private:
  void shape_changed(std::size_t b);  // line and centre from shape[b]
};

// A grain's velocity (vx, vy) relative to a body's surface at the point
// (x, y), in m/s: less the body's velocity (bvx, bvy) where it moves, less
// omega x (point - pivot) where it turns. The one formula of a body's surface
// motion: the contact kernel, the energy ledger and Bodies::velocity_at.
constexpr std::array<double, 2> relative_to_surface(double vx, double vy, bool moving, bool rotating, double bvx,
                                                     double bvy, double omega, double pivot_x, double pivot_y,
                                                     double x, double y) {
  if (moving) vx -= bvx, vy -= bvy;
  if (rotating) vx += omega * (y - pivot_y), vy -= omega * (x - pivot_x);
  return {vx, vy};
}

inline std::array<double, 2> Bodies::velocity_at(std::size_t b, double x, double y) const {
  const std::array<double, 2> r =
      relative_to_surface(0.0, 0.0, true, true, vx[b], vy[b], omega[b], pivot_x[b], pivot_y[b], x, y);
  return {-r[0], -r[1]};
}

}  // namespace dem2d
