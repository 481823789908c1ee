// Cohesion (contact/cohesion.hpp): the law's force against the gap, its
// pull-off force and the work to part a resting pair, against the model's
// analytic values; then the engine: a pair (and a grain on a wall) given
// less kinetic energy than that work stays bound and turns back at the gap
// energy conservation predicts; given more, it parts with the kinetic energy
// left over. The search for candidates reaches beyond the skin by the range.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string_view>
#include <vector>

#include "contact/cohesion.hpp"
#include "contact/contact_model.hpp"
#include "scene_builder.hpp"

namespace dem2d::test {
namespace {

constexpr EffectSet kCohesive = effect::cohesion;
constexpr double kKn = 1.92e6;     // N/m
constexpr double kPull = 0.5;      // f_c (N/m): ~3 weights of a 3 mm glass disk
constexpr double kRange = 1e-4;    // delta_c (m)
constexpr double kD = 3e-3;        // m

ContactLaw cohesive_law() {
  ContactLaw law;
  law.kn = kKn;
  law.cohesion_force = kPull;
  law.cohesion_range = kRange;
  return law;
}

double static_force(const ContactModel<kCohesive>& m, double delta) {
  double ft = 0.0, mr = 0.0;
  return m.eval({delta, 0.0, 0.0, 0.0, 1.0, 1.0}, delta < m.range(), ft, mr).fn;
}

TEST(CohesionLaw, ForceAgainstGapPullOffAndSeparationWork) {
  const ContactModel<kCohesive> m{coefficients(cohesive_law(), 1e-6)};
  EXPECT_EQ(m.range(), kRange);
  EXPECT_DOUBLE_EQ(static_force(m, -1e-6), kKn * 1e-6 - kPull);          // overlap: spring minus f_c
  EXPECT_DOUBLE_EQ(static_force(m, 0.25 * kRange), -0.75 * kPull);      // gap: linear decay
  EXPECT_EQ(static_force(m, kRange), 0.0);                                // out of range
  EXPECT_EQ(static_force(m, 2.0 * kRange), 0.0);
  // equilibrium at overlap f_c/k_n; the largest tension, the pull-off force, is f_c
  const double eq = -kPull / kKn;
  EXPECT_NEAR(static_force(m, eq), 0.0, 1e-12);
  double work = 0.0, tension = 0.0;
  const int n = 200000;
  const double h = (kRange - eq) / n;
  for (int k = 0; k < n; ++k) {  // midpoint rule; the kink at 0 lies on a node
    const double f = static_force(m, eq + (k + 0.5) * h);
    work -= f * h;
    tension = std::max(tension, -f);
  }
  EXPECT_NEAR(tension, kPull, 1e-3 * kPull);
  EXPECT_NEAR(work, cohesive_separation_work(cohesive_law()), 1e-6 * work);
  EXPECT_NEAR(cohesive_separation_work(cohesive_law()), kPull * kPull / (2 * kKn) + 0.5 * kPull * kRange, 1e-20);
}

// Cohesion is one term of the law's list (contact/cohesion.hpp): the scene
// keys, the coefficients and the reach beyond contact come from that list.
TEST(CohesionLaw, TermRegisteredThroughTheLawsList) {
  std::vector<std::string_view> cohesive;
  for (const auto& k : contact_law_keys())
    if (k.needs == effect::cohesion) cohesive.push_back(k.key);
  EXPECT_EQ(cohesive, (std::vector<std::string_view>{"cohesion_force", "cohesion_range"}));
  EXPECT_TRUE(reaches_beyond_contact(kCohesive | effect::friction));
  EXPECT_FALSE(reaches_beyond_contact(kFullMoving));
  const LawCoefficients c = coefficients(cohesive_law(), 1e-6);
  EXPECT_EQ(law_range(c, kCohesive), kRange);
  EXPECT_EQ(law_range(c, kFullMoving), 0.0);
  EXPECT_DOUBLE_EQ(c.coh_k, kPull / kRange);
  ContactLaw steep = cohesive_law();
  steep.cohesion_range = 0.5 * kPull / kKn;  // attraction twice as steep as the spring
  ASSERT_EQ(law_issues(steep, kCohesive).size(), 1u);
  EXPECT_TRUE(law_issues(steep, kFullMoving).empty());
  EXPECT_TRUE(law_issues(cohesive_law(), kCohesive).empty());
}

TEST(CohesionLaw, FrictionCappedByTheLoadPressingTheSurfaces) {
  ContactLaw law = cohesive_law();
  law.kt = 0.5 * kKn;
  law.friction = 0.5;
  const double dt = 1e-6;
  const ContactModel<kCohesive | effect::friction> m{coefficients(law, dt)};
  // at equilibrium the net normal force is zero but f_c presses the surfaces: cap mu f_c
  double ft = 0.0, mr = 0.0;
  const ContactForce f = m.eval({-kPull / kKn, 0.0, 1.0, 0.0, 1.0, 1.0}, true, ft, mr);
  EXPECT_NEAR(f.fn, 0.0, 1e-12);
  EXPECT_NEAR(std::abs(f.ft), 0.5 * kPull, 1e-12);
  // across a gap: attraction, no friction, the spring released
  ft = 0.1;
  const ContactForce g = m.eval({0.5 * kRange, 0.0, 1.0, 0.0, 1.0, 1.0}, true, ft, mr);
  EXPECT_LT(g.fn, 0.0);
  EXPECT_EQ(g.ft, 0.0);
  EXPECT_EQ(ft, 0.0);
}

// Two equal disks at rest at their equilibrium overlap, then pulled apart at
// relative speed v (no damping, friction or gravity). Returns the largest gap
// reached while bound (m) and the final relative speed (m/s, 0 if bound).
struct Parting {
  double max_gap = 0.0;
  double final_speed = 0.0;
};

Parting part_pair(double v, double skin) {
  Scene s = glass_scene(kCohesive, kKn);
  s.particle_particle = cohesive_law();
  s.skin = skin;
  const double eq = kPull / kKn;
  add_disk(s, -0.5 * (kD - eq), 0.0, kD, -0.5 * v);
  add_disk(s, 0.5 * (kD - eq), 0.0, kD, 0.5 * v);
  set_dt_fraction(s, 50.0);
  System sys(s);
  Parting r;
  const int steps = static_cast<int>(0.05 / s.dt);  // 50 ms: many bound oscillations
  for (int k = 0; k < steps; k += 10) {
    sys.advance(10);
    const double gap = sys.state.p.x[1] - sys.state.p.x[0] - kD;
    if (gap > 3.0 * kRange) {
      r.final_speed = sys.state.p.vx[1] - sys.state.p.vx[0];
      return r;
    }
    r.max_gap = std::max(r.max_gap, gap);
  }
  return r;
}

// Gap at which the kinetic energy 1/2 m_eff v^2 is used up (within range).
double turning_gap(double v, double m_eff) {
  const double e = 0.5 * m_eff * v * v - kPull * kPull / (2 * kKn);  // left at contact
  const double k_a = kPull / kRange;                                   // e = f_c g - k_a g^2 / 2
  return (kPull - std::sqrt(kPull * kPull - 2.0 * k_a * e)) / k_a;
}

TEST(Cohesion, PairBoundBelowTheSeparationWorkPartsAboveIt) {
  const double m = kDensity * M_PI * kD * kD / 4.0, m_eff = 0.5 * m;
  const double v_star = std::sqrt(2.0 * cohesive_separation_work(cohesive_law()) / m_eff);
  for (const double skin : {0.5e-3, 0.02e-3}) {  // the second is 5x smaller than the range
    const Parting bound = part_pair(0.95 * v_star, skin);
    EXPECT_EQ(bound.final_speed, 0.0) << "skin " << skin;
    EXPECT_NEAR(bound.max_gap, turning_gap(0.95 * v_star, m_eff), 0.01 * turning_gap(0.95 * v_star, m_eff));
    const Parting parts = part_pair(1.05 * v_star, skin);
    EXPECT_NEAR(parts.final_speed, v_star * std::sqrt(1.05 * 1.05 - 1.0), 0.01 * parts.final_speed) << "skin " << skin;
  }
}

TEST(Cohesion, GrainOnAWallPartsAboveTheSeparationWork) {
  const double m = kDensity * M_PI * kD * kD / 4.0;
  const double v_star = std::sqrt(2.0 * cohesive_separation_work(cohesive_law()) / m);
  for (const double factor : {0.95, 1.05}) {
    Scene s = glass_scene(kCohesive | effect::walls, kKn);
    s.particle_particle = s.particle_wall = cohesive_law();
    add_wall(s, "floor", -0.01, -1e-3, 0.01, -1e-3);  // top face at y = 0
    add_disk(s, 0.0, 0.5 * kD - kPull / kKn, kD, 0.0, factor * v_star);
    set_dt_fraction(s, 50.0);
    System sys(s);
    double top = 0.0;
    for (int k = 0; k < static_cast<int>(0.05 / s.dt) && sys.state.p.y[0] < 0.5 * kD + 3 * kRange; k += 10) {
      sys.advance(10);
      top = std::max(top, sys.state.p.y[0] - 0.5 * kD);
    }
    if (factor < 1.0) {
      EXPECT_LT(top, kRange);
      EXPECT_NEAR(top, turning_gap(factor * v_star, m), 0.01 * top);
    } else {
      EXPECT_NEAR(sys.state.p.vy[0], v_star * std::sqrt(factor * factor - 1.0), 0.01 * sys.state.p.vy[0]);
    }
  }
}

}  // namespace
}  // namespace dem2d::test
