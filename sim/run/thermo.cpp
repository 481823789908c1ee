#include "run/thermo.hpp"

#include <cstdio>

#include "engine/diagnostics.hpp"

namespace dem2d {

std::string thermo_text(const System& sys) {
  const Particles& p = sys.state.p;
  double diameters = 0.0;
  std::size_t active = 0;
  for (std::size_t i = 0; i < sys.size(); ++i)
    if (p.active[i]) diameters += 2.0 * p.radius[i], ++active;
  const double grains = active > 0 ? static_cast<double>(active) : 1.0;
  // a pair contact counts for both of its grains, a wall contact for one
  const auto per_grain = static_cast<double>(contact_count(sys) + pair_contact_count(sys)) / grains;
  char buf[160];
  std::snprintf(buf, sizeof buf, "KE %.3g J/m  contacts/grain %.3g  max overlap/d %.2g  lost %zu",
                kinetic_energy(sys), per_grain, max_overlap(sys) * grains / (diameters > 0.0 ? diameters : 1.0),
                sys.state.lost.size());
  std::string out = buf;
  const Bodies& B = sys.state.bodies;
  for (std::size_t b = 0; b < B.size(); ++b) {
    if (B.vx[b] == 0.0 && B.vy[b] == 0.0 && B.omega[b] == 0.0) continue;  // at rest now
    std::snprintf(buf, sizeof buf, "  F(%s) (%.3g, %.3g) N/m", B.name[b].c_str(), B.fx[b], B.fy[b]);
    out += buf;
  }
  return out;
}

}  // namespace dem2d
