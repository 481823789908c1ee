// Measurements on one snapshot's coarse-grained fields: the mobility zones of
// v* = |V| / V_intruder, the cone's edges and angle, the walls' mobility, the
// solid fraction in a region. Definitions and reasons: analysis/cg/README.md.
// SI units (m, m/s, m^2); angles in degrees. A field value NaN means "no
// velocity there" (outside the bed, see velocity() in cg_field.hpp).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "cg/cg_field.hpp"
#include "common/units.hpp"
#include "frame/intruder.hpp"

namespace dem2d::analysis {

// v* = |V - V_frame| / v_ref per node, NaN where V is NaN.
std::vector<double> speed_ratio(const Velocity& v, double frame_vx, double frame_vy, double v_ref);

// Areas (m^2) of the nodes with v* < lo (immobile), lo <= v* <= hi (cone), v* > hi (dragged).
struct ZoneAreas {
  double immobile = 0.0, cone = 0.0, dragged = 0.0;
};
ZoneAreas zone_areas(const Grid& g, const std::vector<double>& vstar, double lo, double hi);

// The zone grown from the intruder: nodes with v* >= level, 4-connected to a
// seed, a node with v* >= level lying over the intruder (left <= x <= right,
// top <= y <= top + seed_depth). 1 = in the zone.
std::vector<std::uint8_t> zone_from_intruder(const Grid& g, const std::vector<double>& vstar, double level,
                                             const Intruder& in, double seed_depth);

// Area (m^2) of a zone and its highest node above the intruder's top face (m; NaN if empty).
struct ZoneExtent {
  double area = 0.0, height = kNaN;
};
ZoneExtent zone_extent(const Grid& g, const std::vector<std::uint8_t>& zone, const Intruder& in);

// beta of a vertical edge. An edge with beta above it leans inwards: the zone
// narrows upwards, which is not the paper's cone, so the cone's statistics
// leave such edges out. A definition (90 degrees = vertical), not a setting;
// the sensitivity to other cut-offs is sensitivity.max_edge_angles_deg.
inline constexpr double kVerticalEdgeDeg = 90.0;

// One edge of the mobilised zone, row by row from y_start upwards: the zone's
// outermost node on that side of the intruder's centre, until the zone leaves
// the row, reaches the grid's column next to the wall (meets_wall, at wall_y)
// or crosses the centre. A least-squares line x = a + b y through these points
// gives beta = 90 - atan(b * outward) (degrees from the horizontal; exactly 90
// for a vertical edge; below 90 the zone widens upwards, above it narrows).
// NaN if the points span less than min_span.
struct EdgeFit {
  double beta_deg = kNaN;
  double slope = kNaN;   // dx/dy, outward positive
  double x_at_y0 = kNaN; // the fitted line's x at y_start (m)
  double rms = kNaN;     // rms distance of the points from the line, along x (m)
  int points = 0;
  bool meets_wall = false;
  double wall_y = kNaN;  // y of the first row where the zone reaches the wall column (m)
  // Left out by the cut-off max_deg: the edge has an angle and it is above max_deg.
  bool excluded(double max_deg) const { return beta_deg > max_deg; }
};
// The two edges. Both means are over the sides not excluded by max_deg (an
// edge without an angle is not excluded: its wall meeting still counts).
struct ConeFit {
  EdgeFit left, right;
  double beta_deg(double max_deg) const;  // mean beta of those sides (NaN if none has one)
  double wall_y(double max_deg) const;    // mean wall_y of those that meet the wall (NaN if none)
};
ConeFit fit_cone(const Grid& g, const std::vector<std::uint8_t>& zone, const Intruder& in, double y_start,
                 double min_span);

// Mean v* over each row's nodes closer than `band` to the wall face x_face
// (NaN nodes skipped; NaN for a row without any): [ny].
std::vector<double> wall_profile(const Grid& g, const std::vector<double>& vstar, double x_face, double band);
// v* = |V| / v_ref along the node column at x, row by row, with V the
// local-linear kernel regression of the grains' velocities (weights m_i
// G(|r_i - node|), a plane fitted, its value at the node). Near a wall or the
// free surface the kernel's mean (V = p / rho) is the velocity of the grains'
// weighted centroid, ~0.8 w inside the boundary; the plane removes that shift
// for a field varying linearly across the kernel. NaN where `valid[j]` is 0 or
// the fit is singular (fewer than three grains spread in both directions).
// `extras` (if given): per row, the plane's velocity components (x v_ref)
// and its noise per component for unit independent noise on each grain's,
// sqrt(sum_i l_i^2) with l_i the fit's weight of grain i: ~1/sqrt(grains) in
// the bulk, larger where the kernel is cut by the free surface and the plane
// is extrapolated.
struct LocalLinearExtras {
  std::vector<double> vx, vy, gain;
};
std::vector<double> local_linear_profile(const Grid& g, const Kernel& k, const Grains& grains, std::size_t set,
                                         double x, double v_ref, const std::vector<std::uint8_t>& valid,
                                         LocalLinearExtras* extras = nullptr);
// Total height (m) of the rows at y >= y_from whose profile value is >= level.
double mobile_length(const Grid& g, const std::vector<double>& profile, double y_from, double level);

// Mean of `field` over the nodes inside the rectangle (NaN values skipped; NaN if none).
double region_mean(const Grid& g, const std::vector<double>& field, double xmin, double xmax, double ymin,
                   double ymax);

}  // namespace dem2d::analysis
