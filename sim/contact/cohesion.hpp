// Cohesion (effect `cohesion`): a reversible linear adhesion for weakly
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
//
// Scene keys ([contact] and [contact.wall]): cohesion_force, cohesion_range.
#pragma once

#include <algorithm>

#include "contact/contact_law.hpp"

namespace dem2d {

// The adhesive pull (N/m, >= 0) at gap delta, for a contact within range.
inline double cohesive_pull(const LawCoefficients& c, double delta) {
  return std::min(c.coh_f, c.coh_k * (c.coh_range - delta));
}

// Work (J/m) to part a resting pair quasi-statically from equilibrium.
inline double cohesive_separation_work(const ContactLaw& law) {
  return 0.5 * law.cohesion_force * law.cohesion_force / law.kn + 0.5 * law.cohesion_force * law.cohesion_range;
}

}  // namespace dem2d
