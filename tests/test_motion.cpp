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
