// A scene after parsing and validation: every parameter the engine needs, in
// SI units, with particles already generated. Built from a TOML file by
// scene/scene_toml.hpp, or directly by tests and the benchmark.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "contact/contact_law.hpp"
#include "contact/stability.hpp"
#include "core/box.hpp"
#include "core/effects.hpp"
#include "core/run_spec.hpp"

namespace dem2d {

struct ParticleInit {
  double x = 0.0, y = 0.0;    // centre (m)
  double d = 0.0;             // diameter (m)
  double vx = 0.0, vy = 0.0;  // velocity (m/s)
  double omega = 0.0;         // angular velocity (rad/s)
};

// Contact history carried over from an earlier run (the state a stage starts from).
struct InitialContact {
  std::int32_t i = 0;   // grain
  std::int32_t j = -1;  // partner grain (> i), or -1 for the body named `body`
  std::string body;
  double ft = 0.0;      // tangential spring (N/m)
  double mr = 0.0;      // rolling moment on i (N)
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
  bool generic_kernel = false;  // run on the generic kernel even where the build has a specialised one

  std::vector<ParticleInit> particles;
  std::vector<BodySpec> bodies;
  std::string initial_run;                      // run file or checkpoint the grains come from ("" if none)
  std::string initial_source;                   // which state of it: "last snapshot, t = 1.2 s (step 4000)",
                                                // "checkpoint at step 4000"
  std::string initial_digest;                   // FNV-1a of the grains and contacts taken from it (16 hex digits)
  std::vector<InitialContact> initial_contacts;  // its contact history
  JamControl jam;
  OutputSpec output;

  // Smallest grain diameter (m) and mass per unit depth (kg/m), and the time
  // unit dt_c = sqrt(m_min / k_n) with the stiffer of the two laws in use.
  double min_diameter() const;
  double min_mass() const;
  double critical_dt() const;
  // The largest stable time step of this scene (contact/stability.hpp): the
  // smaller of the two laws' limits on a dense packing of the smallest grains.
  StabilityLimit stability_limit() const;
  // Width of the neighbour-search cells (m, NeighbourLists::cell_width): the
  // largest diameter plus the skin plus how far beyond touching the laws act.
  double neighbour_cell_size() const;
  // How far beyond touching contacts act (m), the larger of the two laws in use.
  double interaction_range() const;
};

}  // namespace dem2d
