// Initial particle placements, usable from code (tests, the benchmark) and
// from the scene file's [[generator]] tables (scene/scene_toml.cpp).
//
// Each generator is a plain function of a spec and a seed: the same spec gives
// bit-identical particles on every platform (no std::*_distribution, whose
// output differs between standard libraries).
#pragma once

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "scene/scene.hpp"

namespace dem2d {

// Grains on a triangular lattice inside a polygon.
//
// Sites: rows `spacing * sqrt(3)/2` apart, odd rows shifted by spacing/2,
// anchored at the polygon's bounding-box lower-left corner + d_max/2 in x and y,
// enumerated row by row from the bottom, left to right. A site is used if a disk
// of diameter d_max centred there lies inside the polygon (centre inside, and
// distance to every edge >= d_max/2, up to kTouchTolerance). The first `count`
// usable sites get a grain each; diameters are drawn in site order, uniform in
// [d_min, d_max), from std::mt19937_64(seed) (see uniform01).
struct LatticeSpec {
  std::int64_t count = 0;                     // grains to place (>= 1)
  std::uint64_t seed = 0;                     // diameter draws
  double d_min = 0.0, d_max = 0.0;            // diameter range (m), 0 < d_min <= d_max
  std::vector<std::array<double, 2>> region;  // polygon vertices (m), >= 3, either orientation
  double spacing = 0.0;                       // site spacing (m), >= d_max; <= 0: 1.05 * d_max
  double vx = 0.0, vy = 0.0;                  // initial velocity of every grain (m/s)
};

// Slack (m) allowed when a disk touches the region boundary, so that rounding
// of the anchor coordinates does not drop a site that touches an edge exactly.
inline constexpr double kTouchTolerance = 1e-12;

// Throws std::invalid_argument (plain message, no file context) if the spec is
// invalid or the region holds fewer than `count` sites.
std::vector<ParticleInit> triangular_lattice(const LatticeSpec& spec);

// Usable lattice sites of `spec` (all of them, ignoring count): for messages and
// for sizing a region.
std::int64_t count_lattice_sites(const LatticeSpec& spec);

// Portable uniform draw in [0, 1): the top 53 bits of one 64-bit output.
inline double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// Geometry helpers (also used by the scene reader's checks).
bool point_in_polygon(const std::vector<std::array<double, 2>>& poly, double x, double y);
double distance_to_segment(double px, double py, double ax, double ay, double bx, double by);

}  // namespace dem2d
