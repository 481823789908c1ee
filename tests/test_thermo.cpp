// The physics on a progress line (run/thermo.hpp): the numbers the state has.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "engine/diagnostics.hpp"
#include "run/thermo.hpp"
#include "scene_builder.hpp"

namespace dem2d::test {
namespace {

TEST(Thermo, ProgressLineCarriesTheStatesNumbers) {
  Scene s = boxed_bed(effect::gravity | effect::normal_damping | effect::friction | effect::moving_bodies, 60, 0.02);
  add_wall(s, "intruder", 0.006, 0.004, 0.014, 0.004, 2e-3, 0.0, 0.02);
  System sys(s);
  run_for(sys, 0.4);  // s: fallen and piled up
  const std::string line = thermo_text(sys);
  char ke[32];
  std::snprintf(ke, sizeof ke, "KE %.3g J/m", kinetic_energy(sys));
  EXPECT_EQ(line.rfind(ke, 0), 0u) << line;
  // grains piled in a box: between 1 and 6 contacts each (a pair counts for both)
  const auto active = static_cast<double>(sys.size() - sys.state.lost.size());
  double per_grain = 0.0;
  ASSERT_EQ(std::sscanf(line.c_str() + line.find("contacts/grain ") + 15, "%lf", &per_grain), 1) << line;
  EXPECT_NEAR(per_grain, static_cast<double>(contact_count(sys) + pair_contact_count(sys)) / active, 0.01);
  EXPECT_GT(per_grain, 1.0);
  EXPECT_LT(per_grain, 6.0);
  EXPECT_NE(line.find("lost " + std::to_string(sys.state.lost.size()) + " "), std::string::npos) << line;
  EXPECT_NE(line.find("F(intruder) ("), std::string::npos) << line;  // the moving body, not the walls
  EXPECT_EQ(line.find("F(floor)"), std::string::npos) << line;
}

}  // namespace
}  // namespace dem2d::test
