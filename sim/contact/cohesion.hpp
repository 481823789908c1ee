// Cohesion term (effect cohesion): a reversible linear adhesion for weakly
// cohesive grains, after Luding, "Cohesive, frictional powders: contact
// models for tension", Granular Matter 10, 235 (2008), in its reversible
// form (MercuryDPM's LinearReversibleAdhesiveInteraction):
//
//   pull(delta) = f_c                          delta <= 0 (overlapping)
//               = f_c (1 - delta/delta_c)      0 < delta < delta_c (a gap)
//               = 0                            delta >= delta_c
//   F_n = F_rep - pull,  F_rep = max(0, -k_n delta - c_n v_n) in contact, 0 in the gap
//
// f_c is the pull-off force (N/m): the largest tension a contact holds,
// reached as the surfaces part; delta_c the range of the attraction beyond
// contact (a liquid bridge's rupture distance, a van der Waals cut-off).
// Friction and rolling resistance act only in contact, capped by the load
// that presses the surfaces together, F_rep = F_n + pull (the net normal
// force plus the adhesive pull): mu F_rep, mu_r F_rep.
//
// Work to part a resting pair quasi-statically, from its equilibrium overlap
// f_c/k_n to delta_c:  W = f_c^2/(2 k_n) + f_c delta_c/2   (J/m).
#pragma once

#include <algorithm>
#include <array>
#include <optional>

#include "contact/law_terms.hpp"

namespace dem2d {

struct Cohesion {
  static constexpr EffectSet effect = effect::cohesion;

  struct Params {
    double cohesion_force = 0.0;  // f_c (N/m): the pull-off force
    double cohesion_range = 0.0;  // delta_c (m): the gap at which the attraction ends
  };
  static constexpr std::array<LawKey<Params>, 2> keys{{
      {"cohesion_force", &Params::cohesion_force, effect::cohesion,
       {"pull-off force f_c of a cohesive contact", "N/m", Rule::positive}},
      {"cohesion_range", &Params::cohesion_range, effect::cohesion,
       {"range delta_c of the attraction beyond contact", "m", Rule::positive}},
  }};

  struct Coeffs {
    double coh_f;      // f_c (N/m)
    double coh_k;      // f_c / delta_c (N/m per m of gap)
    double coh_range;  // delta_c (m)
  };
  static Coeffs coefficients(const Params& p, double /*dt*/) {
    return {p.cohesion_force, p.cohesion_range > 0.0 ? p.cohesion_force / p.cohesion_range : 0.0,
            p.cohesion_range};
  }
  static double range(const Coeffs& c) { return c.coh_range; }

  // The attraction's slope f_c/delta_c must not exceed k_n: the time step and
  // its stability limit are set by k_n.
  template <class Law>
  static std::optional<LawIssue> check(const Law& law) {
    if (law.cohesion_force / law.cohesion_range <= law.kn) return std::nullopt;
    return LawIssue{{"cohesion_range", "cohesion_force", "kn"},
                    "the cohesive attraction f_c/delta_c = " + sig3(law.cohesion_force / law.cohesion_range) +
                        " N/m per m is steeper than the contact spring k_n = " + sig3(law.kn) +
                        " N/m; need cohesion_range >= cohesion_force/kn = " + sig3(law.cohesion_force / law.kn) +
                        " m"};
  }

  // After the normal term: the repulsion acts in contact only, the pull in range.
  template <EffectSet E>
  static ContactState apply(const Coeffs& c, const ContactKinematics k, ContactState s, EffectSet /*scene*/) {
    s.touch = s.acts && k.delta < 0.0;
    s.load = s.touch ? s.f.fn : 0.0;
    s.f.fn = s.acts ? s.load - pull(c, k.delta) : 0.0;
    return s;
  }

  // The adhesive pull (N/m, >= 0) at gap delta, for a contact within range.
  static double pull(const Coeffs& c, double delta) { return std::min(c.coh_f, c.coh_k * (c.coh_range - delta)); }
};

// Work (J/m) to part a resting pair quasi-statically from equilibrium.
template <class Law>
double cohesive_separation_work(const Law& law) {
  return 0.5 * law.cohesion_force * law.cohesion_force / law.kn + 0.5 * law.cohesion_force * law.cohesion_range;
}

}  // namespace dem2d
