// Scene files: a full valid scene parses to the right values, the lattice
// generator is deterministic and sound, and every kind of bad input is
// rejected with a message naming the file, line, key, value and allowed range.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <string_view>

#include "engine/kernel_sets.hpp"
#include "scene/generators.hpp"
#include "scene/scene_toml.hpp"
#include "toml/toml_reader.hpp"
#include "scene_builder.hpp"
#include "temp_dir.hpp"

namespace dem2d::test {
namespace {

constexpr const char* kPath = "scenes/t.toml";

// Every effect of the paper's law on; explicit particles, a generator and a moving body.
constexpr std::string_view kValid = R"(name = "drop"
description = "two disks above a lattice on a floor"
[effects]
gravity = true
normal_damping = true
friction = true
rolling_resistance = true
walls = true
moving_bodies = true
[gravity]
g = [0, -9.81]
[material]
density = 2500
[contact]
kn = 1.92e6
kt = 9.6e5
restitution = 0.9
friction = 0.5
rolling_friction = 1.5e-5
rolling_stiffness = 1.728e-6
[contact.wall]
kn = 3.84e6
friction = 0.3
[time]
duration = 0.05
dt_over_critical = 0.02
[stop]
kinetic_energy_below = 1e-9
check_interval = 0.01
min_time = 0.02
[domain]
xmin = -0.05
xmax = 0.05
ymin = -0.01
ymax = 0.2
[neighbour]
skin = 5e-4
[output]
series_interval = 1e-3
snapshot_interval = 0.01
checkpoint_interval = 600
[[particle]]
x = 0.0
y = 0.1
d = 3e-3
vx = 0.1
omega = 2
[[particle]]
x = 0.01
y = 0.1
d = 4e-3
[[generator]]
kind = "triangular_lattice"
count = 50
seed = 7
diameter = { min = 2e-3, max = 4e-3 }
region = [[-0.04, 0.0], [0.04, 0.0], [0.04, 0.05], [-0.04, 0.05]]
velocity = [0, -0.1]
[[body]]
name = "floor"
a = [-0.05, -1e-3]
b = [0.05, -1e-3]
thickness = 2e-3
[[body]]
name = "intruder"
a = [-5e-3, 0.15]
b = [5e-3, 0.15]
thickness = 2e-3
velocity = [0, 1.2e-3]
)";

// No optional table, no effect: two elastic disks.
constexpr std::string_view kBare = R"([material]
density = 2500
[contact]
kn = 1e6
[time]
duration = 1
dt = 1e-6
[domain]
xmin = 0
xmax = 1
ymin = 0
ymax = 1
[[particle]]
x = 0.5
y = 0.5
d = 2e-3
[[particle]]
x = 0.6
y = 0.5
d = 4e-3
)";

// `text` with the first occurrence of `from` replaced by `to`.
std::string edit(std::string_view text, std::string_view from, std::string_view to) {
  std::string s(text);
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << "test bug: '" << from << "' not in the scene";
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

std::string error_of(std::string_view text) {
  try {
    parse_scene(text, kPath);
  } catch (const SceneError& e) {
    return e.what();
  }
  ADD_FAILURE() << "the scene was accepted";
  return "";
}

// The message starts with the file (and line, when given) and contains every part.
void expect_error(std::string_view text, std::initializer_list<std::string_view> parts,
                  int line = 0) {
  const std::string msg = error_of(text);
  const std::string head = std::string(kPath) + (line > 0 ? ":" + std::to_string(line) + ":" : ":");
  EXPECT_EQ(msg.rfind(head, 0), 0u) << "expected prefix '" << head << "' in: " << msg;
  for (const auto part : parts)
    EXPECT_NE(msg.find(part), std::string::npos) << "'" << part << "' missing in: " << msg;
}

TEST(SceneToml, ValidFullScene) {
  const Scene s = parse_scene(kValid, kPath);
  EXPECT_EQ(s.path, kPath);
  EXPECT_EQ(s.text, kValid);
  EXPECT_EQ(s.name, "drop");
  EXPECT_EQ(s.effects, effect::gravity | effect::normal_damping | effect::friction | effect::rolling_resistance |
                           effect::walls | effect::moving_bodies);
  EXPECT_EQ(s.gx, 0.0);
  EXPECT_EQ(s.gy, -9.81);
  EXPECT_EQ(s.density, 2500.0);
  EXPECT_EQ(s.particle_particle.kn, 1.92e6);
  EXPECT_EQ(s.particle_particle.kt, 9.6e5);
  EXPECT_EQ(s.particle_particle.restitution, 0.9);
  EXPECT_EQ(s.particle_particle.friction, 0.5);
  EXPECT_EQ(s.particle_particle.rolling_friction, 1.5e-5);
  EXPECT_EQ(s.particle_particle.rolling_stiffness, 1.728e-6);
  // [contact.wall] overrides kn and friction, inherits the rest.
  EXPECT_EQ(s.particle_wall.kn, 3.84e6);
  EXPECT_EQ(s.particle_wall.friction, 0.3);
  EXPECT_EQ(s.particle_wall.kt, 9.6e5);
  EXPECT_EQ(s.particle_wall.restitution, 0.9);
  EXPECT_EQ(s.particle_wall.rolling_friction, 1.5e-5);
  EXPECT_EQ(s.particle_wall.rolling_stiffness, 1.728e-6);
  ASSERT_EQ(s.particles.size(), 52u);
  // dt_c with the stiffer (wall) law and the smallest grain.
  double d_min = 1.0;
  for (const auto& p : s.particles) d_min = std::min(d_min, p.d);
  const double dt_c = std::sqrt(2500.0 * M_PI * d_min * d_min / 4.0 / 3.84e6);
  EXPECT_DOUBLE_EQ(s.critical_dt(), dt_c);
  EXPECT_DOUBLE_EQ(s.dt, 0.02 * dt_c);
  EXPECT_FALSE(s.dt_forced);
  EXPECT_EQ(s.stop.duration, 0.05);
  EXPECT_EQ(s.stop.kinetic_energy_below, 1e-9);
  EXPECT_EQ(s.stop.check_interval, 0.01);
  EXPECT_EQ(s.stop.min_time, 0.02);
  EXPECT_EQ(s.domain.xmin, -0.05);
  EXPECT_EQ(s.domain.xmax, 0.05);
  EXPECT_EQ(s.domain.ymin, -0.01);
  EXPECT_EQ(s.domain.ymax, 0.2);
  EXPECT_EQ(s.skin, 5e-4);
  EXPECT_EQ(s.threads, 0);
  EXPECT_EQ(s.output.series_interval, 1e-3);
  EXPECT_EQ(s.output.snapshot_interval, 0.01);
  EXPECT_EQ(s.output.checkpoint_interval, 600.0);
  // without the key: a checkpoint every 5 min of wall time, so that a killed run resumes
  EXPECT_EQ(parse_scene(edit(kValid, "checkpoint_interval = 600\n", ""), kPath).output.checkpoint_interval, 300.0);
  // Explicit particles first, in file order, then the generator's.
  EXPECT_EQ(s.particles[0].x, 0.0);
  EXPECT_EQ(s.particles[0].y, 0.1);
  EXPECT_EQ(s.particles[0].d, 3e-3);
  EXPECT_EQ(s.particles[0].vx, 0.1);
  EXPECT_EQ(s.particles[0].vy, 0.0);
  EXPECT_EQ(s.particles[0].omega, 2.0);
  EXPECT_EQ(s.particles[1].d, 4e-3);
  EXPECT_EQ(s.particles[1].vx, 0.0);
  // The generator's first site: bounding-box corner + d_max/2.
  EXPECT_DOUBLE_EQ(s.particles[2].x, -0.04 + 2e-3);
  EXPECT_DOUBLE_EQ(s.particles[2].y, 0.0 + 2e-3);
  EXPECT_EQ(s.particles[2].vy, -0.1);
  ASSERT_EQ(s.bodies.size(), 2u);
  EXPECT_EQ(s.bodies[0].name, "floor");
  EXPECT_EQ(s.bodies[0].vertices[0].x, -0.05);
  EXPECT_EQ(s.bodies[0].vertices[1].y, -1e-3);
  EXPECT_EQ(s.bodies[0].thickness, 2e-3);
  EXPECT_EQ(s.bodies[0].vy, 0.0);
  EXPECT_EQ(s.bodies[1].name, "intruder");
  EXPECT_EQ(s.bodies[1].vy, 1.2e-3);
}

TEST(SceneToml, GeneratedGrainsDependOnlyOnTheSeed) {
  const Scene a = parse_scene(kValid, kPath), b = parse_scene(kValid, "other/path.toml");
  const Scene c = parse_scene(edit(kValid, "seed = 7", "seed = 8"), kPath);
  ASSERT_EQ(c.particles.size(), a.particles.size());
  int differ = 0;
  for (std::size_t i = 2; i < a.particles.size(); ++i) {
    EXPECT_EQ(a.particles[i].x, b.particles[i].x);
    EXPECT_EQ(a.particles[i].y, b.particles[i].y);
    EXPECT_EQ(a.particles[i].d, b.particles[i].d);
    EXPECT_EQ(a.particles[i].y, c.particles[i].y);
    differ += a.particles[i].d != c.particles[i].d;
  }
  EXPECT_EQ(differ, 50);
}

TEST(SceneToml, DefaultsOfABareScene) {
  const Scene s = parse_scene(kBare, "runs/bare_scene.toml");
  EXPECT_EQ(s.name, "bare_scene");  // the file stem
  EXPECT_EQ(s.effects, 0u);
  EXPECT_EQ(s.dt, 1e-6);
  EXPECT_EQ(s.skin, 0.25 * 2e-3);
  EXPECT_EQ(s.stop.kinetic_energy_below, -1.0);  // off
  EXPECT_EQ(s.output.series_interval, 0.0);
  EXPECT_EQ(s.particle_wall.kn, s.particle_particle.kn);
  EXPECT_EQ(s.particles[1].vy, 0.0);
}

TEST(SceneToml, ShippedMinimalSceneIsValid) {
  const std::string path = std::string(DEM2D_DATA_DIR) + "/../tests/scenes/valid_minimal.toml";
  const Scene s = load_scene(path);
  EXPECT_EQ(s.name, "valid_minimal");
  EXPECT_EQ(s.stop.duration, 0.05);
  EXPECT_TRUE(has(s.effects, effect::walls));
  EXPECT_EQ(s.bodies.size(), 1u);
  EXPECT_GT(s.particles.size(), 1u);
}

TEST(SceneToml, DocumentedExampleIsValid) {
  std::ifstream in(std::string(DEM2D_DATA_DIR) + "/../docs/scene_format.md");
  const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto begin = doc.rfind("```toml\n");
  ASSERT_NE(begin, std::string::npos);
  const auto end = doc.find("```", begin + 8);
  const Scene s = parse_scene(std::string_view(doc).substr(begin + 8, end - begin - 8), "example");
  EXPECT_EQ(s.name, "pull_demo");
  EXPECT_EQ(s.particles.size(), 1601u);
  EXPECT_EQ(s.bodies.size(), 4u);
  EXPECT_NEAR(s.dt, 0.0167 * s.critical_dt(), 1e-20);
}

TEST(SceneToml, LoadSceneReadsAFile) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("dem2d_scene_" + std::to_string(::getpid()) + ".toml");
  { std::ofstream(path) << kBare; }
  const Scene s = load_scene(path.string());
  std::filesystem::remove(path);
  EXPECT_EQ(s.path, path.string());
  EXPECT_EQ(s.text, kBare);
  EXPECT_EQ(s.particles.size(), 2u);
}

// ------------------------------------------------------------------ generator

LatticeSpec box_spec(std::uint64_t seed) {
  LatticeSpec spec;
  spec.count = 200;
  spec.seed = seed;
  spec.d_min = 2e-3;
  spec.d_max = 4e-3;
  // An L-shaped (non-convex) region, clockwise.
  spec.region = {{0.0, 0.0}, {0.0, 0.06}, {0.03, 0.06}, {0.03, 0.03}, {0.08, 0.03}, {0.08, 0.0}};
  return spec;
}

TEST(SceneGenerator, SameSeedSameGrainsOtherSeedOtherDiameters) {
  const auto a = triangular_lattice(box_spec(1)), b = triangular_lattice(box_spec(1));
  const auto c = triangular_lattice(box_spec(2));
  ASSERT_EQ(a.size(), 200u);
  ASSERT_EQ(c.size(), 200u);
  int differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x, b[i].x);
    EXPECT_EQ(a[i].y, b[i].y);
    EXPECT_EQ(a[i].d, b[i].d);
    EXPECT_EQ(a[i].x, c[i].x);  // sites do not depend on the seed
    differ += a[i].d != c[i].d;
  }
  EXPECT_GT(differ, 190);
}

TEST(SceneGenerator, PortableDiameterDraws) {
  LatticeSpec spec = box_spec(42);
  spec.count = 3;
  const auto g = triangular_lattice(spec);
  std::mt19937_64 rng(42);
  for (const auto& p : g)
    EXPECT_EQ(p.d, 2e-3 + static_cast<double>(rng() >> 11) * 0x1.0p-53 * 2e-3);
}

TEST(SceneGenerator, GrainsInsideTheRegionAndApart) {
  const LatticeSpec spec = box_spec(3);
  const auto g = triangular_lattice(spec);
  const double spacing = 1.05 * spec.d_max;
  for (std::size_t i = 0; i < g.size(); ++i) {
    EXPECT_GE(g[i].d, spec.d_min);
    EXPECT_LT(g[i].d, spec.d_max);
    EXPECT_TRUE(point_in_polygon(spec.region, g[i].x, g[i].y)) << i;
    for (std::size_t k = 0, j = spec.region.size() - 1; k < spec.region.size(); j = k++)
      EXPECT_GE(distance_to_segment(g[i].x, g[i].y, spec.region[j][0], spec.region[j][1],
                                    spec.region[k][0], spec.region[k][1]),
                0.5 * g[i].d)
          << i;
    for (std::size_t j = 0; j < i; ++j)
      EXPECT_GE(std::hypot(g[i].x - g[j].x, g[i].y - g[j].y), spacing * (1 - 1e-12))
          << i << " " << j;
  }
  // Rows from the bottom, left to right; row 1 shifted by half a spacing.
  EXPECT_DOUBLE_EQ(g[0].x, 2e-3);
  EXPECT_DOUBLE_EQ(g[1].x, 2e-3 + spacing);
  EXPECT_LT(g[0].y, g.back().y);
  const auto row1 =
      std::find_if(g.begin(), g.end(), [&](const ParticleInit& p) { return p.y > g[0].y; });
  ASSERT_NE(row1, g.end());
  EXPECT_DOUBLE_EQ(row1->y, 2e-3 + spacing * std::sqrt(3.0) / 2.0);
  EXPECT_DOUBLE_EQ(row1->x, 2e-3 + spacing / 2.0);
}

TEST(SceneGenerator, TooSmallRegionThrows) {
  LatticeSpec spec = box_spec(1);
  spec.count = 100000;
  EXPECT_THROW(triangular_lattice(spec), std::invalid_argument);
}

// ------------------------------------------------------------------ bad input

TEST(SceneTomlErrors, MissingRequiredKey) {
  expect_error(edit(kValid, "duration = 0.05\n", ""),
               {"missing key time.duration", "simulated time in s, > 0"});
  expect_error(edit(kBare, "kn = 1e6\n", ""), {"missing key contact.kn", "N/m, > 0"}, 3);
  expect_error(edit(kValid, "kt = 9.6e5\n", ""),
               {"missing key contact.kt", ">= 0", "required because effects.friction is true"});
}

TEST(SceneTomlErrors, WrongType) {
  expect_error(edit(kValid, "friction = 0.5", "friction = \"high\""),
               {"contact.friction = \"high\"", "wrong type, expected a number"}, 18);
  expect_error(edit(kValid, "count = 50", "count = 50.0"),
               {"generator[0].count = 50", "expected an integer"});
  expect_error(edit(kValid, "walls = true", "walls = 1"),
               {"effects.walls = 1", "expected a boolean"}, 8);
  expect_error(edit(kValid, "g = [0, -9.81]", "g = [0, \"down\"]"),
               {"gravity.g[1] = \"down\"", "wrong type, expected a number"}, 11);
}

TEST(SceneTomlErrors, NegativeStiffness) {
  expect_error(edit(kValid, "kn = 1.92e6", "kn = -5"), {"contact.kn = -5", "must be > 0", "N/m"},
               15);
  expect_error(edit(kValid, "kt = 9.6e5", "kt = -1.5e5"),
               {"contact.kt = -150000", "must be >= 0", "N/m"}, 16);
  expect_error(edit(kValid, "kn = 3.84e6", "kn = 0"), {"contact.wall.kn = 0", "must be > 0", "N/m"},
               22);
}

TEST(SceneTomlErrors, NegativeFriction) {
  expect_error(edit(kValid, "friction = 0.5", "friction = -0.1"),
               {"contact.friction = -0.1", "must be >= 0"}, 18);
  expect_error(edit(kValid, "friction = 0.3", "friction = -0.3"),
               {"contact.wall.friction = -0.3", ">= 0"}, 23);
}

TEST(SceneTomlErrors, RestitutionOutOfRange) {
  expect_error(edit(kValid, "restitution = 0.9", "restitution = 0"),
               {"contact.restitution = 0", "in (0, 1]"}, 17);
  expect_error(edit(kValid, "restitution = 0.9", "restitution = 1.2"),
               {"contact.restitution = 1.2", "in (0, 1]"}, 17);
  expect_error(edit(kValid, "restitution = 0.9", "restitution = nan"),
               {"contact.restitution = nan", "in (0, 1]"});
}

TEST(SceneTomlErrors, UnknownKeys) {
  expect_error(edit(kValid, "name = \"drop\"", "nmae = \"drop\""),
               {"unknown key 'nmae' at the top level", "allowed: name, description"}, 1);
  expect_error(
      edit(kValid, "friction = 0.5", "frictoin = 0.5"),
      {"unknown key 'frictoin' in [contact]",
       "(allowed: kn, restitution, cohesion_force, cohesion_range, kt, friction, tangential_damping_ratio, "
       "rolling_friction, rolling_stiffness, rolling_damping_ratio, wall)"},
      18);
  expect_error(edit(kValid, "name = \"intruder\"", "name = \"intruder\"\ncolour = \"red\""),
               {"unknown key 'colour' in body[1]", "allowed: name, role, shape, thickness, velocity, motion, motion_repeat, pivot, remove_at, a, b, centre, size, angle, vertices"}, 66);
  expect_error(
      edit(kValid, "{ min = 2e-3, max = 4e-3 }", "{ min = 2e-3, max = 4e-3, mean = 3e-3 }"),
      {"unknown key 'mean' in generator[0].diameter", "allowed: min, max"}, 56);
}

// Times become step counts (core/step_count.hpp); a time of more than 2^53
// steps overflowed them (a run spinning at step 0, a series row every step),
// and a time step that underflows to 0 was accepted. Each is an error at its
// key saying how to say "never" instead.
TEST(SceneTomlErrors, TimesBeyondWhatARunCanCount) {
  expect_error(edit(kValid, "thickness = 2e-3\nvelocity", "thickness = 2e-3\nremove_at = 1e15\nvelocity"),
               {"body[1].remove_at = 1e+15: is ", "steps of dt = ", "more than the 9.01e+15 a run can count",
                "to keep the body, leave remove_at out"});
  expect_error(edit(kValid, "series_interval = 1e-3", "series_interval = 1e15"),
               {"output.series_interval = 1e+15", "to write none, set 0 (off)"}, 39);
  expect_error(edit(kValid, "duration = 0.05", "duration = 1e15"), {"time.duration = 1e+15", "stop it by [stop]"}, 25);
  expect_error(edit(kValid, "min_time = 0.02", "min_time = 1e300"), {"stop.min_time = 1e+300", "more than"}, 30);
  expect_error(edit(kBare, "dt = 1e-6", "dt = 1e-20"), {"time.duration = 1: is 1e+20 steps"}, 6);
  expect_error(edit(kBare, "d = 2e-3", "d = 1e-300"),
               {"time.dt = 1e-06: the smallest grain, particle 0 (particle[0], line 13) (d = 1e-300 m), has dt_c = sqrt(m_min/k_n) = 0 s"}, 7);
}

// The neighbour search's cells must fit in what the engine can index:
// `check` refuses a domain far larger than the grains, as `run` does (where
// it was an exit 1 without the scene's name, after `check` said valid); and a
// 100 000-character unknown key is shown by its start and length.
TEST(SceneTomlErrors, WhatRunRefusesCheckRefuses) {
  expect_error(edit(edit(kValid, "xmax = 0.05", "xmax = 1e3"), "ymax = 0.2", "ymax = 1e3"),
               {"domain.xmax = 1000: the domain", "neighbour-search cells of", "more than the 2e+08 the engine can index"});
  const std::string key(100000, 'k');
  try {
    parse_scene(edit(kValid, "[time]", "[time]\n" + key + " = 1"), kPath);
    FAIL() << "expected an error";
  } catch (const SceneError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("unknown key 'kkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkk... (100000 characters)' in [time]"), std::string::npos) << m.substr(0, 300);
    EXPECT_LT(m.size(), 400u);
  }
}

// [[body]] role: what the analyses find a body by (core/body_roles.hpp).
TEST(SceneToml, BodyRoles) {
  const Scene s = parse_scene(edit(kValid, "name = \"intruder\"", "name = \"intruder\"\nrole = \"intruder\""), kPath);
  EXPECT_EQ(s.bodies[0].role, "");
  EXPECT_EQ(s.bodies[1].role, "intruder");
}

TEST(SceneTomlErrors, BodyRoles) {
  expect_error(edit(kValid, "name = \"intruder\"", "name = \"intruder\"\nrole = \"pusher\""),
               {"body[1].role = \"pusher\"", "unknown role (allowed: intruder, floor, left_wall, right_wall, hopper)"}, 66);
  const std::string two = edit(edit(kValid, "name = \"intruder\"", "name = \"intruder\"\nrole = \"intruder\""),
                               "name = \"floor\"", "name = \"floor\"\nrole = \"intruder\"");
  expect_error(two, {"body[1].role = \"intruder\"", "body[0] 'floor' has this role already (one body at most)"});
  // several hopper walls
  EXPECT_NO_THROW(parse_scene(edit(edit(kValid, "name = \"intruder\"", "name = \"intruder\"\nrole = \"hopper\""),
                                   "name = \"floor\"", "name = \"floor\"\nrole = \"hopper\""), kPath));
}

TEST(SceneTomlErrors, KeyOfADisabledEffect) {
  expect_error(edit(kBare, "kn = 1e6", "kn = 1e6\nkt = 5e5"),
               {"contact.kt = 5e+05", "given but effects.friction is false"}, 5);
  expect_error(edit(kBare, "[material]", "[gravity]\ng = [0, -9.81]\n[material]"),
               {"gravity = { g = [0, -9.81] }", "given but effects.gravity is false"}, 1);
}

TEST(SceneTomlErrors, OverlappingParticles) {
  const std::string overlapping = edit(kValid, "x = 0.01\ny = 0.1", "x = 0.0015\ny = 0.1");
  expect_error(
      overlapping,
      {"particle 0 (particle[0], line 42)", "particle 1 (particle[1], line 48)",
       "overlap by 0.002 m (66.7% of the smaller diameter)", "allow_initial_overlap = true"},
      48);
  EXPECT_NO_THROW(parse_scene("allow_initial_overlap = true\n" + overlapping, kPath));
  // A generated grain on top of an explicit one.
  expect_error(edit(kValid, "y = 0.1\nd = 4e-3", "y = 0.002\nd = 4e-3"),
               {"particle 1 (particle[1], line 48) and particle 13 (grain 11 of generator[0], line "
                "52) overlap by"},
               52);
}

TEST(SceneTomlErrors, ParticleOverlappingABody) {
  const std::string low = edit(kValid, "x = 0.0\ny = 0.1", "x = 0.045\ny = 1e-3");
  expect_error(low,
               {"particle 0 (particle[0], line 42) overlaps body 'floor' by 0.0005 m (16.7% of its "
                "diameter)",
                "allow_initial_overlap"},
               42);
  EXPECT_NO_THROW(parse_scene("allow_initial_overlap = true\n" + low, kPath));
}

TEST(SceneTomlErrors, ParticleOutsideTheDomain) {
  expect_error(
      edit(kValid, "x = 0.01\n", "x = 0.07\n"),
      {"particle 1 (particle[1], line 48) at (x, y) = (0.07, 0.1) m lies outside the domain",
       "[-0.05, 0.05] x [-0.01, 0.2] m"},
      48);
}

TEST(SceneTomlErrors, TimeStepAboveTheStabilityBound) {
  // kBare: undamped normal springs only, so the limit is 2/sqrt(6) dt_c
  // (contact/stability.hpp) with dt_c = sqrt(m_min/k_n) = 8.86e-5 s
  const std::string big = edit(kBare, "dt = 1e-6", "dt = 1e-3");
  expect_error(big,
               {"time.dt = 0.001 s exceeds the stability limit dt_s = 7.24e-05 s = 0.816 dt_c",
                "dt_c = sqrt(m_min/k_n) = 8.86e-05 s", "hexagonal", "d = 0.002 m",
                "grains moving against their normal/tangential springs", "time.force_dt = true"},
               7);
  const Scene forced = parse_scene(edit(big, "[domain]", "force_dt = true\n[domain]"), kPath);
  EXPECT_EQ(forced.dt, 1e-3);
  EXPECT_TRUE(forced.dt_forced);
  // kValid: the wall law (k_n = 3.84e6, k_t = 9.6e5 N/m) is the stiffer; with
  // k_t = k_n/4 its fastest mode is a translation (wave vector M), damped by e = 0.9
  expect_error(
      edit(kValid, "dt_over_critical = 0.02", "dt_over_critical = 0.75"),
      {"time.dt_over_critical = 0.75", "must be <= 0.741", "stability limit",
       "grains moving against their normal/tangential springs (wave vector M)", "time.force_dt = true"},
      26);
  EXPECT_NO_THROW(parse_scene(edit(kValid, "dt_over_critical = 0.02", "dt_over_critical = 0.74"), kPath));
  // one law with k_t = k_n/2: the spin mode, 2/sqrt(12) dt_c = 0.577 dt_c
  const std::string one_law = edit(kValid, "[contact.wall]\nkn = 3.84e6\n", "[contact.wall]\n");
  expect_error(edit(one_law, "dt_over_critical = 0.02", "dt_over_critical = 0.58"),
               {"must be <= 0.577", "grains spinning against their tangential/rolling springs (wave vector Gamma)"});
  EXPECT_NO_THROW(parse_scene(edit(one_law, "dt_over_critical = 0.02", "dt_over_critical = 0.577"), kPath));
  expect_error(edit(kValid, "dt_over_critical = 0.02", "dt_over_critical = 0.02\ndt = 1e-7"),
               {"time.dt_over_critical = 0.02", "give exactly one"}, 26);
}

TEST(SceneToml, DampingEffectsAndTheirRatios) {
  const std::string damped = edit(edit(kValid, "moving_bodies = true\n", "moving_bodies = true\ntangential_damping = true\nrolling_damping = true\n"),
                                  "rolling_stiffness = 1.728e-6\n",
                                  "rolling_stiffness = 1.728e-6\ntangential_damping_ratio = 0.3\nrolling_damping_ratio = 0.2\n");
  const Scene s = parse_scene(damped, kPath);
  EXPECT_EQ(s.effects, kFullMoving);
  EXPECT_EQ(s.particle_particle.tangential_damping_ratio, 0.3);
  EXPECT_EQ(s.particle_wall.rolling_damping_ratio, 0.2);  // inherited by the wall law
  // the ratios are required with their effect, forbidden without it
  expect_error(edit(damped, "tangential_damping_ratio = 0.3\n", ""),
               {"missing key contact.tangential_damping_ratio", "required because effects.tangential_damping is true"});
  expect_error(edit(kValid, "rolling_stiffness = 1.728e-6\n", "rolling_stiffness = 1.728e-6\nrolling_damping_ratio = 0.2\n"),
               {"contact.rolling_damping_ratio = 0.2", "given but effects.rolling_damping is false"});
  expect_error(edit(damped, "tangential_damping_ratio = 0.3", "tangential_damping_ratio = -1"),
               {"contact.tangential_damping_ratio = -1", ">= 0"});
  // a dashpot needs the spring it damps
  expect_error(edit(damped, "friction = true\n", ""),
               {"effects.tangential_damping = true", "needs effects.friction = true"});
}

TEST(SceneToml, CohesionKeysAndTheirBounds) {
  const std::string cohesive = edit(edit(kValid, "moving_bodies = true\n", "moving_bodies = true\ncohesion = true\n"),
                                    "rolling_stiffness = 1.728e-6\n",
                                    "rolling_stiffness = 1.728e-6\ncohesion_force = 0.5\ncohesion_range = 1e-4\n");
  const Scene s = parse_scene(cohesive, kPath);
  EXPECT_TRUE(has(s.effects, effect::cohesion));
  EXPECT_EQ(s.particle_particle.cohesion_force, 0.5);
  EXPECT_EQ(s.particle_wall.cohesion_range, 1e-4);  // inherited by the wall law
  expect_error(edit(cohesive, "cohesion_range = 1e-4\n", ""),
               {"missing key contact.cohesion_range", "required because effects.cohesion is true"});
  expect_error(edit(kValid, "rolling_stiffness = 1.728e-6\n", "rolling_stiffness = 1.728e-6\ncohesion_force = 0.5\n"),
               {"contact.cohesion_force = 0.5", "given but effects.cohesion is false"});
  // an attraction steeper than the contact spring: f_c/delta_c = 5e7 > k_n = 1.92e6
  expect_error(edit(cohesive, "cohesion_range = 1e-4", "cohesion_range = 1e-8"),
               {"contact.cohesion_range = 1e-08", "steeper than the contact spring", "need cohesion_range >= "});
  // [contact.wall] may override it, and is checked against its own k_n
  expect_error(edit(cohesive, "friction = 0.3\n", "friction = 0.3\ncohesion_force = 1e3\n"),
               {"contact.wall.cohesion_force = 1000", "steeper than the contact spring k_n = 3.84e+06"});
  expect_error(edit(cohesive, "checkpoint_interval = 600\n", "checkpoint_interval = 600\nenergy_balance = true\n"),
               {"output.energy_balance = true", "does not yet count the cohesive potential"});
}

TEST(SceneToml, BodyMotionSchedules) {
  const std::string cyclic = edit(kValid, "velocity = [0, 1.2e-3]",
                                  "motion = [\n  { kind = \"hold\", duration = 0.5 },\n"
                                  "  { kind = \"sine\", amplitude = [0, 0.02], period = 4.0, cycles = 3 },\n"
                                  "  { kind = \"constant\", velocity = [0, 1.2e-3] },\n]");
  const Scene s = parse_scene(cyclic, kPath);
  const BodySpec& blade = s.bodies.back();
  ASSERT_EQ(blade.motion.size(), 3u);
  EXPECT_EQ(blade.motion[1].kind, MotionKind::sine);
  EXPECT_EQ(blade.motion[1].cycles, 3);
  EXPECT_EQ(blade.motion[1].ay, 0.02);
  EXPECT_TRUE(std::isinf(blade.motion[2].duration));  // the last constant segment goes on
  EXPECT_EQ(blade.motion_repeat, 1);
  expect_error(edit(cyclic, "kind = \"hold\"", "kind = \"wobble\""),
               {"body[1].motion[0].kind = \"wobble\"", "unknown motion kind (allowed: hold, constant, ramp, sine, triangle)"});
  expect_error(edit(cyclic, "period = 4.0", "period = 4.0, duration = 2"),
               {"body[1].motion[1].duration = 2", "a sine segment does not take it"});
  expect_error(edit(cyclic, "period = 4.0, ", ""), {"missing key body[1].motion[1].period", "(sine)"});
  // a segment shorter than a time step (a subnormal 1e-310 s turned the grains to NaN at the first step)
  for (const char* t : {"1e-310", "1e-12"}) {
    expect_error(edit(cyclic, "duration = 0.5", std::string("duration = ") + t),
                 {std::string("body[1].motion[0].duration = ") + t, "shorter than one time step"});
    expect_error(edit(cyclic, "period = 4.0", std::string("period = ") + t),
                 {std::string("body[1].motion[1].period = ") + t, "shorter than one time step"});
  }
  expect_error(edit(cyclic, "cycles = 3", "cycles = 0"), {"body[1].motion[1].cycles = 0", "integer in [1, 1000000]"});
  // integers range-checked as the type they are stored in, never wrapped (4294967297 ran one cycle) nor
  // unrolled into a schedule that cannot fit in memory (1e9 cycles)
  for (const char* n : {"4294967297", "2147483648", "1000000000", "1000001"})
    expect_error(edit(cyclic, "cycles = 3", std::string("cycles = ") + n),
                 {std::string("body[1].motion[1].cycles = ") + n, "1000000"});
  const std::string repeated = edit(cyclic, "{ kind = \"constant\", velocity = [0, 1.2e-3] },\n", "");
  EXPECT_EQ(parse_scene(edit(repeated, "motion = [", "motion_repeat = 1000\nmotion = ["), kPath).bodies.back().motion_repeat,
            1000);
  expect_error(edit(repeated, "motion = [", "motion_repeat = 4294967297\nmotion = ["),
               {"body[1].motion_repeat = 4294967297", "1000000"});
  expect_error(edit(repeated, "motion = [", "motion_repeat = 500000\nmotion = ["),
               {"body[1].motion_repeat = 500000", "more than 1000000 pieces"});
  expect_error(edit(cyclic, "motion = [", "velocity = [0, 1]\nmotion = ["), {"give either velocity or motion"});
  expect_error(edit(cyclic, "motion = [", "motion_repeat = 2\nmotion = ["),
               {"body[1].motion_repeat = 2", "lasts for ever", "cannot repeat"});
  expect_error(edit(edit(cyclic, "velocity = [0, 1.2e-3] }", "velocity = [0, 1.2e-3], duration = 1 }"),
                    "{ kind = \"hold\", duration = 0.5 }", "{ kind = \"constant\", velocity = [0, 1] }"),
               {"missing key body[1].motion[0].duration", "(constant)"});
}

// A turning schedule: angular_velocity in constant and ramp segments, angle in cycles,
// about the body's pivot; each needs effects.rotating_bodies, which needs a turn.
TEST(SceneToml, TurningSchedules) {
  const std::string turning = edit(edit(kValid, "moving_bodies = true\n", "moving_bodies = true\nrotating_bodies = true\n"),
                                   "velocity = [0, 1.2e-3]",
                                   "pivot = [0.05, 0.0]\nmotion = [\n  { kind = \"ramp\", angular_velocity = 2.0, duration = 0.5 },\n"
                                   "  { kind = \"triangle\", angle = 0.3, period = 1.0 },\n"
                                   "  { kind = \"constant\", velocity = [0, 1e-3], angular_velocity = -1.0 },\n]");
  const Scene s = parse_scene(turning, kPath);
  const BodySpec& blade = s.bodies.back();
  ASSERT_EQ(blade.motion.size(), 3u);
  EXPECT_EQ(blade.motion[0].w, 2.0);
  EXPECT_EQ(blade.motion[0].vx, 0.0);  // a turn alone
  EXPECT_EQ(blade.motion[1].aw, 0.3);
  EXPECT_EQ(blade.motion[2].vy, 1e-3);
  EXPECT_EQ(blade.motion[2].w, -1.0);
  ASSERT_TRUE(blade.pivot.has_value());
  EXPECT_EQ(blade.pivot->x, 0.05);
  expect_error(edit(turning, "rotating_bodies = true\n", ""),
               {"body[1].motion[0].angular_velocity = 2", "needs effects.rotating_bodies = true"});
  expect_error(edit(turning, "angular_velocity = 2.0, ", ""),
               {"missing key body[1].motion[0].velocity", "or angular_velocity"});
  expect_error(edit(turning, "{ kind = \"ramp\", angular_velocity = 2.0, duration = 0.5 }",
                    "{ kind = \"hold\", angular_velocity = 2.0, duration = 0.5 }"),
               {"body[1].motion[0].angular_velocity = 2", "a hold segment does not take it"});
  expect_error(edit(turning, "angle = 0.3", "angle = \"a lot\""), {"body[1].motion[1].angle"});
  expect_error(edit(edit(edit(turning, "angular_velocity = 2.0, ", "velocity = [0, 1], "), "angle = 0.3", "amplitude = [0, 1]"),
                    ", angular_velocity = -1.0", ""),
               {"effects.rotating_bodies = true", "no [[body]] motion turns"});
  expect_error(edit(kValid, "velocity = [0, 1.2e-3]", "velocity = [0, 1.2e-3]\npivot = [0, 0]"),
               {"body[1].pivot", "the body has no motion to turn it"});
  // a pivot far beyond the domain (1e300 collapsed the wall to a point without a word)
  for (const char* far : {"[1e300, 0.0]", "[0.05, -1e3]"})
    expect_error(edit(turning, "pivot = [0.05, 0.0]", std::string("pivot = ") + far),
                 {"body[1].pivot", "lies farther from the domain"});
}

TEST(SceneTomlErrors, BodiesNeedWalls) {
  const std::string body = "[[body]]\nname = \"w\"\na = [0, 0]\nb = [1, 0]\nthickness = 1e-3\n";
  expect_error(std::string(kBare) + body, {"[[body]] given but effects.walls is false"}, 21);
  expect_error(
      edit(kValid, "walls = true\nmoving_bodies = true\n", ""),
      {"contact.wall = { friction = 0.3, kn = 3840000 }", "given but effects.walls is false"}, 19);
  expect_error(edit(kValid, "walls = true\n", ""), {"effects.moving_bodies = true", "needs effects.walls = true"}, 8);
  expect_error(edit(kBare, "[material]", "[effects]\nwalls = true\n[material]"),
               {"effects.walls = true", "no [[body]]"}, 2);
}

// Every valid set is read: the study's on its specialised kernel, one that
// sim/engine/kernel_sets.inc does not declare on the generic kernel. An
// effect switched off with its keys kept is the keys' error, not the kernel's.
TEST(SceneTomlErrors, EveryValidEffectSetIsRead) {
  static_assert(parse_effect_set("friction,gravity") == (effect::gravity | effect::friction));
  static_assert(parse_effect_set("") == EffectSet{0});
  static_assert(!parse_effect_set("gravity,,friction") && !parse_effect_set("gravity,") &&
                !parse_effect_set("gravity,gravity") && !parse_effect_set("gravitation"));
  const EffectSet study = parse_scene(kValid, kPath).effects;
  EXPECT_TRUE(kernels_specialised(study));
  EXPECT_EQ(kernel_description(study).rfind("kernel specialised for {", 0), 0u);
  const EffectSet paddle = study & ~effect::rolling_resistance & ~effect::normal_damping;  // declared by no line
  ASSERT_FALSE(kernels_specialised(paddle));
  EXPECT_EQ(kernel_description(paddle).rfind("generic kernel for {gravity,friction,walls,moving_bodies}", 0), 0u);
  expect_error(edit(kValid, "normal_damping = true\n", ""),
               {"contact.restitution = 0.9", "given but effects.normal_damping is false"}, 16);
}

TEST(SceneTomlErrors, MovingBodyNeedsMovingBodies) {
  expect_error(edit(kValid, "moving_bodies = true\n", ""),
               {"body[1].velocity = [0, 0.0012]", "needs effects.moving_bodies = true"}, 68);
  expect_error(edit(kValid, "velocity = [0, 1.2e-3]", ""),
               {"effects.moving_bodies = true", "no [[body]] has"}, 9);
}

TEST(SceneTomlErrors, DuplicateBodyNames) {
  expect_error(edit(kValid, "name = \"intruder\"", "name = \"floor\""),
               {"body[1].name = \"floor\"", "duplicate name", "body[0]"}, 65);
}

TEST(SceneTomlErrors, GeneratorRegionTooSmall) {
  expect_error(edit(kValid, "count = 50", "count = 5000"),
               {"generator[0]: the region holds only", "fewer than count = 5000"}, 52);
  expect_error(edit(kValid, "seed = 7", "seed = 7\nspacing = 3e-3"),
               {"generator[0].spacing = 0.003", "must be >= generator[0].diameter.max = 0.004"});
  expect_error(edit(kValid, "kind = \"triangular_lattice\"", "kind = \"random\""),
               {"generator[0].kind = \"random\"", "allowed: triangular_lattice"}, 53);
  // a region of 1e300 m: an error at once (the scan over it never ended)
  expect_error(edit(kValid, "[0.04, 0.05], [-0.04, 0.05]]", "[1e300, 1e300], [-0.04, 0.05]]"),
               {"generator[0]: the region's bounding box spans", "more than the 1e+09 a generator scans"}, 52);
  expect_error(
      edit(kValid, "[-0.04, 0.05]]", "[-0.04]]"),
      {"generator[0].region[3] = [-0.04]", "must be an array [x, y] (polygon vertex in m, finite)"},
      57);
}

// Overlays (presets, sweep settings) merged over a scene file.
Scene with_overlays(const TempDir& dir, std::initializer_list<std::string_view> overlays) {
  SceneSources extra;
  int n = 0;
  for (std::string_view o : overlays) {
    std::string name = "o";
    name += std::to_string(n++);
    name += ".toml";
    extra.overlays.push_back(dir.file(name, std::string(o)));
  }
  return load_scene(dir.file("scene.toml", std::string(kValid)), extra);
}

// An overlay that gives a body another shape replaces its outline keys (the
// study's INTRUDER=square) and keeps the rest (its velocity).
TEST(SceneOverlays, AnotherShapeReplacesTheOutline) {
  TempDir dir;
  const Scene s = with_overlays(dir, {"[[body]]\nname = \"intruder\"\nshape = \"rectangle\"\ncentre = [0, 0.15]\n"
                                      "size = [0.01, 0.002]\nthickness = 0.0\n"});
  const BodySpec& in = s.bodies[1];
  EXPECT_EQ(in.shape, "rectangle");
  ASSERT_EQ(in.vertices.size(), 4u);
  EXPECT_EQ(in.vertices[0].x, -0.005);
  EXPECT_EQ(in.vertices[2].y, 0.151);
  EXPECT_EQ(in.vy, 1.2e-3);
}

TEST(SceneOverlays, TablesMergeKeyByKeyAndOtherValuesReplace) {
  TempDir dir;
  const Scene s = with_overlays(dir, {"[contact]\nkn = 3e6\n[gravity]\ng = [0, -1.62]\n", "[contact]\nfriction = 0.3\n"});
  EXPECT_EQ(s.particle_particle.kn, 3e6);        // first overlay
  EXPECT_EQ(s.particle_particle.friction, 0.3);  // second overlay
  EXPECT_EQ(s.particle_particle.kt, 9.6e5);      // the scene's, kept
  EXPECT_EQ(s.gy, -1.62);                        // an array replaces
  EXPECT_NE(s.text.find("o0.toml + "), std::string::npos) << "the stored text names the overlays";
}

TEST(SceneOverlays, NamedBodiesMergeByNameAndNewNamesAreAdded) {
  TempDir dir;
  const Scene s = with_overlays(dir, {"[[body]]\nname = \"intruder\"\nvelocity = [0, 2.4e-3]\n"
                                      "[[body]]\nname = \"lid\"\na = [-0.05, 0.19]\nb = [0.05, 0.19]\nthickness = 2e-3\n"});
  ASSERT_EQ(s.bodies.size(), 3u);
  EXPECT_EQ(s.bodies[0].name, "floor");
  EXPECT_EQ(s.bodies[0].vertices[0].y, -1e-3);   // untouched
  EXPECT_EQ(s.bodies[1].name, "intruder");
  EXPECT_EQ(s.bodies[1].vy, 2.4e-3);  // merged
  EXPECT_EQ(s.bodies[1].vertices[0].x, -5e-3);   // its other keys kept
  EXPECT_EQ(s.bodies[2].name, "lid");
}

TEST(SceneOverlays, UnnamedArraysOfTablesReplaceAndErrorsNameTheOverlay) {
  TempDir dir;
  const Scene s = with_overlays(dir, {"[[particle]]\nx = 0.02\ny = 0.12\nd = 3e-3\n"});
  EXPECT_EQ(s.particles.size(), 1u + 50u) << "one explicit particle replaces the two, plus the generator's 50";
  try {
    with_overlays(dir, {"[contact]\nkn = -1\n"});
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("o0.toml:2:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("contact.kn = -1"), std::string::npos) << e.what();
  }
}

TEST(SceneTomlErrors, UnreadableFile) {
  try {
    load_scene("scenes/does_not_exist.toml");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_STREQ(
        e.what(),
        "scenes/does_not_exist.toml: cannot read the scene file: No such file or directory");
  }
}

// What is not a scene file is refused before it is read: a device that never
// ends (/dev/zero used to be read until memory ran out), a directory, a file
// larger than any scene.
TEST(SceneTomlErrors, NotARegularFileOrTooLarge) {
  const auto message = [](const std::string& path) {
    try {
      load_scene(path);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("/dev/zero"), "/dev/zero: cannot read the scene file: not a regular file");
  const TempDir dir;
  EXPECT_EQ(message(dir.path().string()), dir.path().string() + ": cannot read the scene file: not a regular file");
  const std::string big = dir.file("big.toml", "#\n");
  std::filesystem::resize_file(big, TomlFile::kMaxBytes + 1);  // sparse: no disk used
  EXPECT_EQ(message(big), big + ": cannot read the scene file: larger than 256 MiB, more than any scene or settings file");
}

TEST(SceneTomlErrors, TomlSyntaxError) {
  expect_error(edit(kValid, "density = 2500", "density = = 2500"), {"TOML syntax error"}, 13);
  expect_error(edit(kValid, "[time]", "[time"), {"TOML syntax error"}, 24);
}

}  // namespace
}  // namespace dem2d::test
