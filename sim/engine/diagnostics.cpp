#include "engine/diagnostics.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>
#include <limits>

#include "contact/contact_model.hpp"

namespace dem2d {

namespace {

// Calls f(slot) for every touching slot of a list.
template <class List, class F>
void for_touching(const List& L, F&& f) {
  for (std::size_t s = 0; s < L.overlap.size(); ++s)
    if (L.overlap[s] > 0.0) f(s);
}

template <class List>
Stored list_spring_energy(const List& L, const ContactLaw& law, EffectSet effects) {
  Stored e;
  for_touching(L, [&](std::size_t s) { e += spring_energy(law, effects, L.overlap[s], L.ft[s], L.mr[s]); });
  return e;
}

}  // namespace

double kinetic_energy(const System& sys) {
  const Particles& p = sys.state.p;
  double e = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.active[i])
      e += 0.5 * p.mass[i] * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i]) +
           0.5 * p.omega[i] * p.omega[i] / p.inv_inertia[i];
  return e;
}

bool kinetic_energy_criterion_met(const System& sys, const StopCondition& stop) {
  const double ke = kinetic_energy(sys);
  if (stop.kinetic_energy_per_grain_below > 0.0) {
    const auto active = static_cast<double>(std::count(sys.state.p.active.begin(), sys.state.p.active.end(), 1));
    return ke < stop.kinetic_energy_per_grain_below * active;
  }
  return stop.kinetic_energy_below > 0.0 && ke < stop.kinetic_energy_below;
}

Stored spring_energy(const System& sys) {
  Stored e = list_spring_energy(sys.state.lists.pairs, sys.config.law_pp, sys.config.effects);
  if (has(sys.config.effects, effect::walls)) e += list_spring_energy(sys.state.lists.walls, sys.config.law_pw, sys.config.effects);
  return e;
}

double elastic_energy(const System& sys) { return spring_energy(sys).total(); }

double gravity_energy(const System& sys) {
  const Particles& p = sys.state.p;
  double e = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.active[i]) e -= p.mass[i] * (sys.config.gx * p.x[i] + sys.config.gy * p.y[i]);
  return e;
}

double highest_grain(const System& sys) {
  double h = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < sys.state.p.size(); ++i)
    if (sys.state.p.active[i]) h = std::max(h, sys.state.p.y[i]);
  return h;
}

double bed_surface_beside(const System& sys, std::size_t b) {
  const Bounds core = core_bounds(sys.state.bodies.shape[b]);
  const double margin = sys.state.bodies.radius[b] + 2.0 * sys.state.lists.r_max();
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < sys.state.p.size(); ++i)
    if (sys.state.p.active[i] && (sys.state.p.x[i] < core.xmin - margin || sys.state.p.x[i] > core.xmax + margin))
      top = std::max(top, sys.state.p.y[i] + sys.state.p.radius[i]);
  return top;
}

bool held_by_bed(const System& sys, std::size_t b) {
  const PairList& L = sys.state.lists.pairs;
  const WallList& W = sys.state.lists.walls;
  const std::size_t n = sys.size();
  const bool gaps = reaches_beyond_contact(sys.config.effects);  // grains held across a gap hold too
  std::vector<std::uint8_t> seen(n, 0), anchored(n, 0);  // anchored: touches another body
  std::vector<std::size_t> queue;
  for (std::size_t s = 0; s < W.slots(); ++s) {
    if (!acted(W.overlap[s], gaps)) continue;
    const auto i = static_cast<std::size_t>(W.owner[s]);
    if (static_cast<std::size_t>(W.body[s]) == b) {
      if (!seen[i]) queue.push_back(i);
      seen[i] = 1;
    } else {
      anchored[i] = 1;
    }
  }
  for (std::size_t q = 0; q < queue.size(); ++q) {  // breadth-first over touching pairs
    const std::size_t i = queue[q];
    if (anchored[i]) return true;
    auto visit = [&](std::size_t s, std::size_t k) {
      if (acted(L.overlap[s], gaps) && !seen[k]) {
        seen[k] = 1;
        queue.push_back(k);
      }
    };
    for (auto s = static_cast<std::size_t>(L.start[i]); s < static_cast<std::size_t>(L.start[i + 1]); ++s)
      visit(s, static_cast<std::size_t>(L.partner[s]));
    for (auto r = static_cast<std::size_t>(L.rev_start[i]); r < static_cast<std::size_t>(L.rev_start[i + 1]); ++r) {
      const auto s = static_cast<std::size_t>(L.rev_slot[r]);
      visit(s, static_cast<std::size_t>(L.owner[s]));
    }
  }
  return false;
}

double max_overlap(const System& sys) {
  double m = 0.0;
  for (const double o : sys.state.lists.pairs.overlap) m = std::max(m, o);
  for (const double o : sys.state.lists.walls.overlap) m = std::max(m, o);
  return m;
}

std::size_t pair_contact_count(const System& sys) {
  std::size_t c = 0;
  for_touching(sys.state.lists.pairs, [&](std::size_t) { ++c; });
  return c;
}

std::size_t contact_count(const System& sys) {
  std::size_t c = pair_contact_count(sys);
  for_touching(sys.state.lists.walls, [&](std::size_t) { ++c; });
  return c;
}

}  // namespace dem2d
