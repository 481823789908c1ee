// Sphero-line geometry (paper eq. 1-3, docs/paper.md): the three cases agree with the paper's
// formulas and join continuously at the flat/cap boundary.
#include <gtest/gtest.h>

#include <cmath>

#include "shape/spheroline.hpp"
#include "scene_builder.hpp"

namespace dem2d::test {
namespace {

// The paper's piecewise definition, written out literally, for comparison.
double paper_distance(double ox, double oy, double c1x, double c1y, double c2x, double c2y) {
  const double cx = 0.5 * (c1x + c2x), cy = 0.5 * (c1y + c2y);
  const double len = std::hypot(c2x - c1x, c2y - c1y);
  const double ux = (c2x - c1x) / len, uy = (c2y - c1y) / len, vx = -uy, vy = ux;
  const double along = (ox - cx) * ux + (oy - cy) * uy;
  if (along <= -len / 2) return std::hypot(ox - c1x, oy - c1y);  // eq. 1
  if (along >= len / 2) return std::hypot(ox - c2x, oy - c2y);   // eq. 2
  return std::abs((ox - cx) * vx + (oy - cy) * vy);              // eq. 3
}

TEST(SpheroLine, MatchesPaperEquations) {
  const Segment s = make_segment(0.01, 0.02, 0.03, 0.035);
  for (double ox = -0.01; ox <= 0.05; ox += 0.0013)
    for (double oy = 0.0; oy <= 0.06; oy += 0.0017)
      EXPECT_NEAR(closest_point(s, ox, oy).dist, paper_distance(ox, oy, 0.01, 0.02, 0.03, 0.035), 1e-15);
}

// A centre exactly on the segment (flat side or end point) has no direction
// to the closest point: it is pushed out along the segment's left normal.
TEST(SpheroLine, CentreOnTheSegmentIsPushedAlongItsNormal) {
  const Segment s = make_segment(0.0, 0.0, 0.03, 0.04);  // |C1C2| = 0.05, u = (0.6, 0.8)
  for (const double t : {0.0, 0.5, 1.0}) {
    const Proximity c = closest_point(s, 0.03 * t, 0.04 * t);
    EXPECT_EQ(c.dist, 0.0) << "t = " << t;
    EXPECT_NEAR(c.nx, -0.8, 1e-15) << "t = " << t;
    EXPECT_NEAR(c.ny, 0.6, 1e-15) << "t = " << t;
  }
  const Proximity off = closest_point(s, -0.8e-3, 0.6e-3);  // 1 mm from C1 along the normal
  EXPECT_NEAR(off.dist, 1e-3, 1e-15);
  EXPECT_NEAR(off.nx, -0.8, 1e-12);
  EXPECT_NEAR(off.ny, 0.6, 1e-12);
}

// A grain slid along the top of a horizontal sphero-line, over its end and
// down around the cap: the overlap and the normal change by at most
// O(step) between neighbouring positions, including across the boundary.
TEST(SpheroLine, OverlapAndNormalAreContinuousAcrossFlatCapBoundary) {
  const double r = 1.5e-3, rs = 1e-3, half = 5e-3;
  const Segment s = make_segment(-half, 0.0, half, 0.0);
  const double h = r + rs - 1e-5;  // 10 um overlap on the flat
  const double step = 1e-7;
  double prev_delta = 0.0, prev_nx = 0.0, prev_ny = 0.0;
  bool first = true;
  double max_jump_delta = 0.0, max_jump_n = 0.0;
  for (double x = half - 1e-4; x <= half + 1e-4; x += step) {
    const Proximity c = closest_point(s, x, h);
    const double delta = c.dist - (r + rs);
    if (!first) {
      max_jump_delta = std::max(max_jump_delta, std::abs(delta - prev_delta));
      max_jump_n = std::max(max_jump_n, std::hypot(c.nx - prev_nx, c.ny - prev_ny));
    }
    first = false;
    prev_delta = delta;
    prev_nx = c.nx;
    prev_ny = c.ny;
  }
  EXPECT_LE(max_jump_delta, step);                   // |d delta / dx| <= 1
  EXPECT_LE(max_jump_n, 2.0 * step / (r + rs));       // |d n / dx| <= 1/distance
  // and the limits on both sides of the boundary agree
  const Proximity flat = closest_point(s, half - 1e-12, h), cap = closest_point(s, half + 1e-12, h);
  EXPECT_NEAR(flat.dist, cap.dist, 1e-14);
  EXPECT_NEAR(flat.nx, cap.nx, 1e-9);
  EXPECT_NEAR(flat.ny, cap.ny, 1e-12);
}

// The same, dynamically: a disk pushed along a horizontal bar slides off its
// end over the cap; the contact force never jumps between steps.
TEST(SpheroLine, GrainSlidingOffTheEndFeelsSmoothForce) {
  Scene s = glass_scene(effect::gravity | effect::normal_damping | effect::walls);
  add_wall(s, "bar", -5e-3, 0.0, 5e-3, 0.0, 2e-3);
  const double d = 3e-3;
  add_disk(s, 3e-3, 1e-3 + 0.5 * d, d, 0.05, 0.0);
  set_dt_fraction(s, 50.0);
  System sys(s);
  double prev_fy = -1.0, max_jump = 0.0, peak = 0.0;
  bool crossed = false;
  while (sys.state.p.y[0] > -0.01) {
    sys.advance(1);
    const double fy = sys.state.p.fy[0];
    if (prev_fy >= 0.0) max_jump = std::max(max_jump, std::abs(fy - prev_fy));
    prev_fy = fy;
    peak = std::max(peak, fy);
    crossed |= sys.state.p.x[0] > 5e-3 && sys.state.lists.walls.overlap[0] > 0.0;
  }
  EXPECT_TRUE(crossed);  // it was in contact with the cap
  // weight m g per unit depth ~ 0.17 N/m; no step changes the force by more than a few % of it
  const double weight = kDensity * M_PI * d * d / 4.0 * 9.81;
  EXPECT_LT(max_jump, 0.05 * weight);
  EXPECT_GT(peak, 0.5 * weight);
}

}  // namespace
}  // namespace dem2d::test
