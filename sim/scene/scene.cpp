#include "scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "neighbour/contact_lists.hpp"  // NeighbourLists::cell_width

namespace dem2d {

double Scene::min_diameter() const {
  double d_min = std::numeric_limits<double>::infinity();
  for (const auto& p : particles) d_min = std::min(d_min, p.d);
  return d_min;
}

double Scene::min_mass() const {
  const double d_min = min_diameter();
  return density * M_PI * d_min * d_min / 4.0;
}

double Scene::critical_dt() const {
  double kn = particle_particle.kn;
  if (has(effects, effect::walls)) kn = std::max(kn, particle_wall.kn);
  return std::sqrt(min_mass() / kn);
}

double Scene::interaction_range() const {
  const double pp = law_range(coefficients(particle_particle, dt), effects);
  return std::max(pp, has(effects, effect::walls) ? law_range(coefficients(particle_wall, dt), effects) : 0.0);
}

double Scene::neighbour_cell_size() const {
  double d_max = 0.0;
  for (const ParticleInit& p : particles) d_max = std::max(d_max, p.d);
  return NeighbourLists::cell_width(0.5 * d_max, skin, interaction_range());
}

StabilityLimit Scene::stability_limit() const {
  StabilityLimit limit = dem2d::stability_limit(particle_particle, effects, density, min_diameter());
  if (has(effects, effect::walls)) {
    // a grain's wall contacts are as stiff as the wall law: the crystal of that law bounds them
    const StabilityLimit wall = dem2d::stability_limit(particle_wall, effects, density, min_diameter());
    if (wall.dt < limit.dt) limit = wall;
  }
  limit.dt_over_critical = limit.dt / critical_dt();
  return limit;
}

}  // namespace dem2d
