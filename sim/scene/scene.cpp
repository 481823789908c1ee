#include "scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dem2d {

double Scene::min_mass() const {
  double d_min = std::numeric_limits<double>::infinity();
  for (const auto& p : particles) d_min = std::min(d_min, p.d);
  return density * M_PI * d_min * d_min / 4.0;
}

double Scene::critical_dt() const {
  double kn = particle_particle.kn;
  if (has(effects, effect::walls)) kn = std::max(kn, particle_wall.kn);
  return std::sqrt(min_mass() / kn);
}

}  // namespace dem2d
