// Synthetic pull-off snapshots with planted truth, for the cg and network
// stages' detectors: a bed of disks on a triangular lattice in the study's
// cell, the intruder rising through it at constant speed, and what is
// planted on it: PIV-like velocities (a mobilised cone of angle beta from the
// intruder's tips, the rest at rest, per-grain noise), a dilated layer above
// the intruder, and force networks (arches from the intruder's ends to the
// walls up to a loss height, keystones ejected at ruptures, random strong
// contacts as noise). Grains keep their lattice positions unless a case
// moves them: the detectors read velocities, displacements, solid fractions
// and contacts, not dynamics. SI units.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "common/events.hpp"
#include "common/snapshot_source.hpp"

namespace dem2d::planted {

struct BedGeometry {
  double width = 0.100;        // cell between the walls' inner faces (m)
  double bed_height = 0.141;   // lattice rows up to here (m)
  double spacing = 0.0034;     // lattice spacing (m)
  double d_min = 0.002, d_max = 0.004;  // diameters, uniform (m)
  double density = 2500.0;     // kg/m^3
  double length = 0.010;       // intruder tip to tip (m)
  double thickness = 0.002;    // intruder (and walls, floor) rounding diameter (m)
  double speed = 0.0012;       // intruder (m/s)
  double start = 0.003;        // intruder centre at t = 0 (m)
  std::uint64_t seed = 1;
};

// The bed: grain centres and diameters on the lattice (a tenth of the spacing jittered).
struct Bed {
  BedGeometry g;
  std::vector<Vec2> position;
  std::vector<double> diameter, mass;
  std::vector<std::pair<std::int32_t, std::int32_t>> neighbours;  // lattice neighbours i < j
  double solid_fraction = 0.0;  // the grains' area over the lattice's (width x bed height)
};
Bed make_bed(const BedGeometry& g);

// A snapshot of the bed at time t: the grains at `position`, the walls, the
// floor and the intruder at its height start + speed t.
Snapshot bed_snapshot(const Bed& bed, const std::vector<Vec2>& position, double t, std::size_t index);
double intruder_height(const BedGeometry& g, double t);

// A cone from the intruder's tips at beta (degrees from the horizontal), the
// paper's zones: the grains above the intruder between its tips move up with
// it (v* = 1), those beside them move up at v* falling linearly with the
// distance from the tips' verticals, through 0.25 at the cone's edge and on to
// 0 (graded: the v* = 0.25 contour is the cone's edge, and a smooth field keeps
// its contours under coarse-graining); else v* = 1 up to the edge and 0 beyond
// (a step, which coarse-graining widens). Gaussian noise of `noise` x speed
// per component on each grain, independent between grains or, with
// `correlation_d` > 0, smoothed over that many mean diameters (as PIV's
// interrogation windows correlate neighbouring vectors); independent between
// snapshots. Snapshots every `travel` m
// of the intruder up to `end`, PIV window `window` s. With `dilation` > 0 the
// snapshots after the first have the layer above the intruder (from 4 w below
// the dilatancy region to 4 w above it; region: cg.toml's) stretched
// vertically by 1 + dilation, w = 1.5 x mean diameter; `jitter` moves every
// grain by a Gaussian of that many mean diameters at every snapshot. The
// right edge may have its own angle (`beta_right_deg`), and both edges may
// bend: at height a above the intruder an edge reaches a / tan(beta) x (1 +
// bend x a / G) beyond its tip, G the gap from a tip to its wall (bend > 0:
// the edge flattens upwards, < 0: it steepens; 0: straight).
struct ConeScenario {
  double beta_deg = 60.0, noise = 0.0, travel = 0.0005, end = 0.140, window = 0.05;
  double beta_right_deg = std::numeric_limits<double>::quiet_NaN();  // NaN: beta_deg
  double bend = 0.0;
  double dilation = 0.0, jitter = 0.0;
  double correlation_d = 0.0;  // noise correlation length, x mean diameter (0: independent per grain)
  double at_rest = 0.0;        // fraction of the snapshots (drawn at random) in which nothing moves
  bool moving = true;  // false: no cone, every grain at rest (but for the noise)
  bool graded = true;  // v* falling linearly across the cone's edge (else a step there)
  // vortices beside the tips: the grains within swirl_radius_d mean diameters of a point that far outside
  // each tip (at the intruder's centre height) turn about it at swirl x V / d, the two sides opposite ways
  double swirl = 0.0, swirl_radius_d = 2.0;
  std::uint64_t seed = 1;
};
analysis::MemorySource cone_run(const Bed& bed, const ConeScenario& c);
// The height above the intruder's top (m) at which an edge of angle beta_deg
// and that bend meets its wall, G (m) from its tip; NaN if it never does.
double wall_meeting(double beta_deg, double bend, double gap);

// Force networks: weak contacts between lattice neighbours and with the
// walls, floor and intruder; arches of strong contacts from the grain at each
// intruder tip to each wall while the intruder is below `loss` (m; above it the
// same arches end 15 mm short of the walls); a fraction `spurious` of all
// contacts made strong at random. Snapshots every `travel` m up to `end`.
struct NetworkScenario {
  double loss = 0.100, spurious = 0.0, travel = 0.001, end = 0.140;
  double lapse = 0.0;  // fraction of the snapshots below the loss (at random) whose arches end short too
  std::uint64_t seed = 1;
};
analysis::MemorySource network_run(const Bed& bed, const NetworkScenario& n);

// Rupture events with keystones: `events` events, each a pair of snapshots
// (before at the peak, after at the drop's end, 0.1 s apart) with the intruder
// in the lower bed; arches to both walls before each; a fraction `ejected` of
// the events (every k-th) moves the grain at an intruder tip (the keystone)
// 1.5 of its diameters down, below the intruder, by the after snapshot; every
// grain also moves by a Gaussian of `jitter` mean diameters.
struct KeystoneScenario {
  int events = 20;
  double ejected = 0.5, spurious = 0.0, jitter = 0.0;
  std::uint64_t seed = 1;
};
struct KeystoneRun {
  analysis::MemorySource source;
  std::vector<analysis::RuptureEvent> events;
  int planted_ejections = 0;
};
KeystoneRun keystone_run(const Bed& bed, const KeystoneScenario& k);

}  // namespace dem2d::planted
