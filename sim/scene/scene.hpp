// A scene after parsing and validation: every parameter the engine needs, in
// SI units, with particles already generated. Built from a TOML file by
// scene/scene_toml.hpp, or directly by tests and the benchmark.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "contact/contact_law.hpp"
#include "core/effects.hpp"

namespace dem2d {

struct ParticleInit {
  double x = 0.0, y = 0.0;    // centre (m)
  double d = 0.0;             // diameter (m)
  double vx = 0.0, vy = 0.0;  // velocity (m/s)
  double omega = 0.0;         // angular velocity (rad/s)
};

struct BodySpec {
  std::string name;
  double ax = 0.0, ay = 0.0, bx = 0.0, by = 0.0;  // segment end points C1, C2 (m)
  double thickness = 0.0;                          // cap diameter d_s (m)
  double vx = 0.0, vy = 0.0;                       // prescribed velocity (m/s)
};

struct Box {
  double xmin = 0.0, ymin = 0.0, xmax = 0.0, ymax = 0.0;  // (m)
  bool contains(double x, double y) const { return x >= xmin && x <= xmax && y >= ymin && y <= ymax; }
};

struct StopCondition {
  double duration = 0.0;                // simulated time limit (s); the run always ends here
  double kinetic_energy_below = -1.0;   // end earlier once total kinetic energy < this (J/m); <0: off
  double check_interval = 0.0;          // how often the energy criterion is tested (s)
  double min_time = 0.0;                // the criterion is not tested before this time (s)
};

struct OutputSpec {
  double series_interval = 0.0;      // body force/torque time series (s); 0 = none
  double snapshot_interval = 0.0;    // particle snapshots with contact lists (s); 0 = none
  double checkpoint_interval = 0.0;  // wall-clock seconds between checkpoints; 0 = none
};

struct Scene {
  std::string path;  // file the scene came from ("" if built in code)
  std::string text;  // its full text, stored in the run file
  std::string name;

  EffectSet effects = 0;
  double gx = 0.0, gy = 0.0;  // gravity (m/s^2)
  double density = 0.0;       // grain density rho (kg/m^3)
  ContactLaw particle_particle;
  ContactLaw particle_wall;

  double dt = 0.0;          // time step (s)
  bool dt_forced = false;   // accept dt above the stability bound
  StopCondition stop;
  Box domain;               // grains leaving it are removed and reported
  double skin = 0.0;        // Verlet-list skin (m)
  int threads = 0;          // 0: OpenMP default

  std::vector<ParticleInit> particles;
  std::vector<BodySpec> bodies;
  OutputSpec output;

  // Smallest grain mass per unit depth (kg/m) and the stability bound
  // dt_c = sqrt(m_min / k_n) with the stiffer of the two laws in use.
  double min_mass() const;
  double critical_dt() const;
};

}  // namespace dem2d
