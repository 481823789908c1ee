// Scheduled motion (core/motion.hpp): positions and velocities at the
// schedule's corners are the closed-form values (holds, constant segments,
// ramps, sine and triangle cycles, repeats); the engine places a body
// exactly where the schedule puts it at every step and hands the contacts
// the velocity over the step; a velocity set during the run (a tap) takes over.
#include <gtest/gtest.h>

#include <cmath>

#include "core/motion.hpp"
#include "scene_builder.hpp"

namespace dem2d::test {
namespace {

// hold 0.5 s; up at 2 mm/s for 1 s; ramp to 1 mm/s down over 0.4 s; two sine
// cycles of 10 mm sideways, 0.8 s each; one triangle cycle 4 mm down, 1 s; twice.
std::vector<MotionSegment> segments() {
  std::vector<MotionSegment> s(5);
  s[0].kind = MotionKind::hold, s[0].duration = 0.5;
  s[1].kind = MotionKind::constant, s[1].duration = 1.0, s[1].vy = 2e-3;
  s[2].kind = MotionKind::ramp, s[2].duration = 0.4, s[2].vy = -1e-3;
  s[3].kind = MotionKind::sine, s[3].ax = 0.01, s[3].period = 0.8, s[3].cycles = 2;
  s[4].kind = MotionKind::triangle, s[4].ay = -0.004, s[4].period = 1.0;
  return s;
}

TEST(Motion, CornersAreWhereTheFormulasPutThem) {
  const MotionSchedule m(segments(), 2);
  const std::vector<double> corners = m.corners();
  // pieces: hold, constant, ramp, sine, sine, triangle; twice; then the end
  ASSERT_EQ(corners.size(), 13u);
  const double run = 0.5 + 1.0 + 0.4 + 1.6 + 1.0;
  EXPECT_NEAR(corners[12], 2 * run, 1e-14);
  const double ramp = 0.5 * (2e-3 - 1e-3) * 0.4;  // (v0 + v1) T / 2
  for (int r = 0; r < 2; ++r) {
    const double t0 = r * run, y0 = r * (2e-3 + ramp);
    auto at = [&](double t) { return m.at(t0 + t); };
    EXPECT_NEAR(at(0.0).y, y0, 1e-15);
    EXPECT_EQ(at(0.25).vy, 0.0);                       // holding
    EXPECT_NEAR(at(0.5).y, y0, 1e-15);
    EXPECT_NEAR(at(0.5).vy, 2e-3, 1e-15);              // constant from its first instant
    EXPECT_NEAR(at(1.0).y, y0 + 1e-3, 1e-15);
    EXPECT_NEAR(at(1.5).y, y0 + 2e-3, 1e-15);
    EXPECT_NEAR(at(1.5).vy, 2e-3, 1e-15);              // the ramp starts from the velocity before it
    EXPECT_NEAR(at(1.7).vy, 0.5e-3, 1e-15);            // linear
    EXPECT_NEAR(at(1.9 - 1e-12).vy, -1e-3, 1e-14);
    EXPECT_NEAR(at(1.9).y, y0 + 2e-3 + ramp, 1e-15);
    // sine cycles: out to 10 mm at half a period, back, at rest at both ends
    EXPECT_NEAR(at(1.9).vx, 0.0, 1e-18);
    EXPECT_NEAR(at(1.9 + 0.2).vx, 0.5 * 0.01 * 2 * M_PI / 0.8, 1e-15);
    EXPECT_NEAR(at(1.9 + 0.4).x, 0.01, 1e-15);
    EXPECT_NEAR(at(1.9 + 0.8).x, 0.0, 1e-15);
    EXPECT_NEAR(at(1.9 + 1.2).x, 0.01, 1e-15);
    EXPECT_NEAR(at(3.5).x, 0.0, 1e-15);
    // triangle: 4 mm down in 0.5 s at 8 mm/s, back
    EXPECT_NEAR(at(3.5 + 0.25).vy, -8e-3, 1e-15);
    EXPECT_NEAR(at(3.5 + 0.5).y, y0 + 2e-3 + ramp - 0.004, 1e-15);
    EXPECT_NEAR(at(3.5 + 0.75).vy, 8e-3, 1e-15);
  }
  // after the schedule: holds where it ended
  EXPECT_NEAR(m.at(100.0).y, 2 * (2e-3 + ramp), 1e-15);
  EXPECT_EQ(m.at(100.0).vy, 0.0);
}

TEST(Motion, ASchedulesThatCannotRunAreRefused) {
  std::vector<MotionSegment> s = segments();
  EXPECT_THROW(MotionSchedule(s, 0), std::invalid_argument);
  s[1].duration = std::numeric_limits<double>::infinity();  // for ever, but not last
  EXPECT_THROW(MotionSchedule(s, 1), std::invalid_argument);
  s = {segments()[1]};
  s[0].duration = std::numeric_limits<double>::infinity();
  EXPECT_NO_THROW(MotionSchedule(s, 1));
  EXPECT_THROW(MotionSchedule(s, 2), std::invalid_argument);
  EXPECT_NEAR(MotionSchedule(s, 1).at(1e4).y, 20.0, 1e-12);  // goes on
}

TEST(Motion, EngineFollowsTheScheduleStepByStep) {
  Scene s = glass_scene(effect::walls | effect::moving_bodies);
  add_disk(s, 0.5, 0.5, 3e-3);  // far away
  add_wall(s, "blade", 0.0, 0.0, 0.01, 0.0);
  s.bodies[0].motion = segments();
  s.bodies[0].motion_repeat = 2;
  s.dt = 1.3e-3;  // corners fall between steps
  const MotionSchedule m(segments(), 2);
  System sys(s);
  for (int k = 0; k < 7500; ++k) {  // 9.75 s: past the end (9 s)
    const double t = static_cast<double>(sys.state.step) * s.dt;
    const MotionSchedule::State at = m.at(t), mid = m.at(t - 0.5 * s.dt);
    ASSERT_EQ(sys.state.bodies.shape[0].x0(), 0.0 + at.x) << "step " << sys.state.step;
    ASSERT_EQ(sys.state.bodies.shape[0].y0(), 0.0 + at.y) << "step " << sys.state.step;
    ASSERT_NEAR(sys.state.bodies.shape[0].vertex(1).x - sys.state.bodies.shape[0].x0(), 0.01, 1e-15);  // translated, not turned
    if (sys.state.step > 0) {
      ASSERT_EQ(sys.state.bodies.vx[0], mid.vx);
      ASSERT_EQ(sys.state.bodies.vy[0], mid.vy);
    }
    sys.advance(1);
  }
  EXPECT_EQ(sys.state.bodies.vy[0], 0.0);  // held after the end
  // a velocity set during the run takes over from where the body is
  const double y = sys.state.bodies.shape[0].y0();
  sys.set_body_velocity(0, 0.0, 1e-3);
  sys.advance(100);
  EXPECT_NEAR(sys.state.bodies.shape[0].y0(), y + 100 * s.dt * 1e-3, 1e-15);
}

}  // namespace
}  // namespace dem2d::test

namespace dem2d::test {
namespace {

// A turn: at rest 0.2 s, a quarter turn per second for 2 s, a ramp of the angular
// velocity to 0 over 1 s while the pivot moves up at 1 mm/s, a sine nod of 0.3 rad.
std::vector<MotionSegment> turning() {
  std::vector<MotionSegment> s(4);
  s[0].kind = MotionKind::hold, s[0].duration = 0.2;
  s[1].kind = MotionKind::constant, s[1].duration = 2.0, s[1].w = 0.5 * M_PI;
  s[2].kind = MotionKind::ramp, s[2].duration = 1.0, s[2].vy = 1e-3, s[2].w = 0.0;
  s[3].kind = MotionKind::sine, s[3].aw = 0.3, s[3].period = 0.5;
  return s;
}

TEST(Motion, AnglesAtTheCornersAreTheClosedFormOnes) {
  const MotionSchedule m(turning(), 1);
  EXPECT_TRUE(m.turns());
  EXPECT_FALSE(MotionSchedule(segments(), 1).turns());
  EXPECT_EQ(m.at(0.1).angle, 0.0);
  EXPECT_NEAR(m.at(1.2).angle, 0.5 * M_PI, 1e-15);
  EXPECT_NEAR(m.at(2.2).angle, M_PI, 1e-15);
  EXPECT_NEAR(m.at(2.2).omega, 0.5 * M_PI, 1e-15);
  EXPECT_NEAR(m.at(2.7).omega, 0.25 * M_PI, 1e-15);                // the ramp, halfway
  EXPECT_NEAR(m.at(3.2).angle, M_PI + 0.25 * M_PI, 1e-15);       // + (w0 + 0) T / 2
  EXPECT_NEAR(m.at(3.2).y, 0.5e-3, 1e-18);                         // the pivot's own ramp
  EXPECT_NEAR(m.at(3.45).angle, 1.25 * M_PI + 0.3, 1e-15);         // the nod's peak
  EXPECT_NEAR(m.at(9.0).angle, 1.25 * M_PI, 1e-15);                // after it: holds
  EXPECT_EQ(m.at(9.0).omega, 0.0);
}

// A blade turned about a pivot that is not on it: at every step its ends are where
// the closed form puts them (pivot + R(angle) (end - pivot)), the contacts get the
// angular velocity over the step, the torque is about the pivot; after 50 turns the
// blade is back where it started to round-off, with no drift.
TEST(Motion, EngineTurnsABodyAboutItsPivotExactly) {
  Scene s = glass_scene(effect::walls | effect::moving_bodies | effect::rotating_bodies);
  s.domain = {-0.05, -0.05, 0.05, 0.05};  // (a small cell grid: the turning blade has the lists rebuilt often)
  add_disk(s, 0.045, 0.045, 3e-3);        // out of the blade's reach
  add_wall(s, "blade", 0.01, 0.0, 0.03, 0.0);
  const double w = 2.0 * M_PI;  // one turn a second
  s.bodies[0].motion.resize(1);
  s.bodies[0].motion[0].kind = MotionKind::constant;
  s.bodies[0].motion[0].duration = std::numeric_limits<double>::infinity();
  s.bodies[0].motion[0].w = w;
  s.bodies[0].pivot = Point{0.0, 0.0};
  s.dt = 1e-3;
  System sys(s);
  const Bodies& B = sys.state.bodies;
  for (int k = 0; k < 2000; ++k) {
    const double angle = w * static_cast<double>(sys.state.step) * s.dt;
    ASSERT_NEAR(B.shape[0].x0(), 0.01 * std::cos(angle), 1e-16) << "step " << sys.state.step;
    ASSERT_NEAR(B.shape[0].y0(), 0.01 * std::sin(angle), 1e-16) << "step " << sys.state.step;
    ASSERT_NEAR(B.shape[0].vertex(1).x, 0.03 * std::cos(angle), 1e-16);
    ASSERT_NEAR(B.shape[0].vertex(1).y, 0.03 * std::sin(angle), 1e-16);
    ASSERT_NEAR(B.line[0].ex, 0.02 * std::cos(angle), 1e-16);  // the edge turned with it
    if (sys.state.step > 0) {
      ASSERT_EQ(B.omega[0], w);
    }
    sys.advance(1);
  }
  // the surface velocity is omega x r: at the far end 0.03 m from the pivot
  const std::array<double, 2> v = B.velocity_at(0, 0.0, 0.03);
  EXPECT_NEAR(v[0], -w * 0.03, 1e-15);
  EXPECT_NEAR(v[1], 0.0, 1e-15);
  sys.advance(48000);  // 50 turns in all
  EXPECT_NEAR(B.shape[0].x0(), 0.01, 1e-15);
  EXPECT_NEAR(B.shape[0].y0(), 0.0, 1e-15);
  EXPECT_NEAR(B.shape[0].vertex(1).x, 0.03, 1e-15);
  // a velocity set during the run ends the turning: the blade keeps its angle
  sys.advance(250);  // a quarter turn on: along +y
  sys.set_body_velocity(0, 1e-3, 0.0);
  sys.advance(100);
  EXPECT_EQ(B.omega[0], 0.0);
  EXPECT_NEAR(B.shape[0].vertex(1).x - B.shape[0].x0(), 0.0, 1e-15);
  EXPECT_NEAR(B.shape[0].vertex(1).y - B.shape[0].y0(), 0.02, 1e-15);
  EXPECT_NEAR(B.shape[0].x0(), 100 * s.dt * 1e-3, 1e-15);
}

// A turning blade hits a grain at rest: the surface under it moves at omega x r,
// and the grain leaves at (1 + e) omega r, as off a wall translating at omega r
// (e = 0.9); the grains' torque on the blade is about the pivot. (The contact's
// own view of the surface velocity is checked by the energy ledger's closure in
// a turning drum, test_energy_ledger.cpp: a linear dashpot's rebound does not
// tell it.)
TEST(Motion, TurningSurfaceHitsLikeAWallMovingAtOmegaCrossR) {
  Scene s = glass_scene(effect::gravity | effect::normal_damping | effect::friction | effect::rolling_resistance |
                        effect::walls | effect::moving_bodies | effect::rotating_bodies);
  s.gy = 0.0;                                         // (the drum's kernels, without the weight)
  add_wall(s, "blade", 0.01, 0.0, 0.03, 0.0);         // 2 mm thick: its top face at y = 1 mm
  add_disk(s, 0.02, 1e-3 + 1.5e-3 + 1e-5, 3e-3);      // 10 um above it, 20 mm from the pivot
  s.bodies[0].motion.resize(1);
  s.bodies[0].motion[0].kind = MotionKind::constant;
  s.bodies[0].motion[0].duration = std::numeric_limits<double>::infinity();
  s.bodies[0].motion[0].w = 1.0;  // rad/s: the surface under the grain rises at 20 mm/s
  s.bodies[0].pivot = Point{0.0, 0.0};
  set_dt_fraction(s, 50.0);
  System sys(s);
  double torque_error = 0.0, peak = 0.0;
  while (static_cast<double>(sys.state.step) * s.dt < 3e-3) {
    sys.advance(1);
    const Bodies& B = sys.state.bodies;
    const WallList& W = sys.state.lists.walls;
    for (std::size_t sl = 0; sl < W.slots(); ++sl)
      if (W.fn[sl] > 0.0) {  // the moment of the contact's force about the pivot (0, 0), and its rolling moment
        torque_error =
            std::max(torque_error, std::abs(B.torque[0] + (W.cx[sl] * W.fy[sl] - W.cy[sl] * W.fx[sl]) + W.mr[sl]));
        peak = std::max(peak, std::abs(B.torque[0]));
      }
  }
  EXPECT_GT(peak, 0.0);
  EXPECT_LT(torque_error, 1e-12 * peak);
  EXPECT_NEAR(sys.state.p.vy[0], 1.9 * 0.02, 0.01 * 0.038);
}

}  // namespace
}  // namespace dem2d::test
