// What a run is given besides its grains and contact laws, as both the scene
// (scene/scene.hpp, from its TOML file) and the run file's /parameters
// (runfile/run_parameters.hpp, read back) hold it: the bodies at t = 0, the
// hopper's jam control, the stop criteria, the output schedule. SI units.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/motion.hpp"
#include "shape/shape.hpp"

namespace dem2d {

struct BodySpec {
  std::string name;
  std::string role;                                // what it is for (core/body_roles.hpp); "" none
  std::string shape = "segment";                   // its scene kind (shape/shape_kinds.hpp)
  std::vector<Point> vertices;                     // core outline at t = 0 (m): a point, a segment's ends
                                                   // C1, C2, or a convex polygon counter-clockwise
  double thickness = 0.0;                          // rounding diameter (a segment's cap diameter d_s) (m)
  double vx = 0.0, vy = 0.0;                       // prescribed velocity (m/s)
  double remove_at = -1.0;                         // time the body is taken away (s); < 0: never
  std::vector<MotionSegment> motion;               // scheduled motion instead of `velocity` (empty: none)
  int motion_repeat = 1;                           // runs of the whole schedule
  std::optional<Point> pivot;                      // what the motion turns the body about, at t = 0 (m);
                                                   // default the mean of the core's vertices

  // A static sphero-line C1C2 (the paper's walls), for scenes built in code.
  static BodySpec segment(std::string name, double ax, double ay, double bx, double by, double thickness) {
    BodySpec b;
    b.name = std::move(name);
    b.vertices = {{ax, ay}, {bx, by}};
    b.thickness = thickness;
    return b;
  }
};

// Clogging of a hopper outlet: when no grain has left the hopper (crossed
// below outlet_height) for no_flow_time while grains remain above it, the
// hopper walls are tapped: moved at tap_velocity for half of tap_duration,
// then back. The run stops, saying so, if max_taps taps did not empty it.
struct JamControl {
  bool enabled = false;
  double outlet_height = 0.0;   // (m)
  double start_time = 0.0;      // no jam is looked for before this time (s), e.g. gate opening
  double no_flow_time = 0.0;    // (s)
  double check_interval = 0.0;  // (s)
  std::vector<std::string> bodies;
  double tap_vx = 0.0, tap_vy = 0.0;  // (m/s)
  double tap_duration = 0.0;          // (s)
  int max_taps = 0;
};

struct StopCondition {
  double duration = 0.0;                // simulated time limit (s); the run always ends here
  double kinetic_energy_below = -1.0;   // end earlier once total kinetic energy < this (J/m); <0: off
  double kinetic_energy_per_grain_below = -1.0;  // ... or once it is < this per active grain (J/m); <0: off
  double all_below = 1e300;             // ... and every active grain is below this height (m)
  std::string body_free;                // end once this body has been free of the bed for free_time:
                                        // no grain touching it connects, through touching grains, to a
                                        // grain touching another body (grains it carries do not count)
  double free_time = 0.0;               // (s)
  double check_interval = 0.0;          // how often the criteria are tested (s)
  double min_time = 0.0;                // the criteria are not tested before this time (s)

  bool energy_criterion() const { return kinetic_energy_below > 0.0 || kinetic_energy_per_grain_below > 0.0; }
};

struct OutputSpec {
  double series_interval = 0.0;      // body force/torque time series (s); 0 = none
  double snapshot_interval = 0.0;    // particle snapshots with contact lists (s); 0 = none
  double checkpoint_interval = 0.0;  // wall-clock seconds between checkpoints; 0 = none
  double displacement_window = 0.0;  // each scheduled snapshot also stores every grain's
                                     // displacement over this past interval (s), a PIV-like
                                     // velocity = displacement / window; 0 = none
  bool energy_balance = false;       // keep the energy ledger (engine/energy_ledger.hpp) and record
                                     // its terms in the series; costs two passes over the contacts a step
};

}  // namespace dem2d
