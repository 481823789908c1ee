// Normal term: a linear spring with (effect normal_damping) a viscous
// dashpot, never attractive (docs/paper.md, "Contact model"):
//
//   F_n = max(0, -k_n delta - c_n vn),  c_n = 2 nu sqrt(m_eff k_n)
//
// with nu the damping ratio that gives the scene's restitution e under this
// law (damping_ratio below). The load that caps friction is F_n.
#pragma once

#include <array>
#include <cmath>
#include <string_view>

#include "contact/law_terms.hpp"

namespace dem2d {

// Restitution of a head-on collision under the normal law above,
// F_n = max(0, k x + c x') with x the overlap: the force vanishes before the
// overlap does (when x'' = 0), the grains then part at constant speed, so
//   e(nu) = exp(-2 nu arccos(nu) / sqrt(1 - nu^2))     nu < 1
//         = exp(-2)                                     nu = 1
//         = exp(-2 nu arccosh(nu) / sqrt(nu^2 - 1))     nu > 1
// (Schwager & Poeschel, Granular Matter 9, 465 (2007); derivation in
// docs/contact_law.md). The familiar exp(-pi nu / sqrt(1 - nu^2)) holds only
// for a law that may pull: with it, e = 0.5 would give 0.551 here.
double restitution_of_damping_ratio(double nu);

// The damping ratio nu >= 0 that gives restitution e in (0, 1] under this
// law: the inverse of restitution_of_damping_ratio (monotone), solved to
// round-off. nu(1) = 0; nu -> 1/(2 sqrt(e)) as e -> 0.
double damping_ratio(double restitution);

struct NormalLaw {
  static constexpr EffectSet effect = 0;

  struct Params {
    double kn = 0.0;           // normal stiffness (N/m)
    double restitution = 1.0;  // normal coefficient of restitution e, in (0, 1]
  };
  static constexpr std::array<LawKey<Params>, 2> keys{{
      {"kn", &Params::kn, 0, {"normal stiffness", "N/m", Rule::positive}},
      {"restitution", &Params::restitution, effect::normal_damping,
       {"normal coefficient of restitution", "", Rule::unit_open_closed}},
  }};

  struct Coeffs {
    double kn;    // N/m
    double damp;  // 2 nu sqrt(k_n): c_n = damp * sqrt(m_eff)  (sqrt(N/m))
  };
  static Coeffs coefficients(const Params& p, double /*dt*/) {
    return {p.kn, 2.0 * damping_ratio(p.restitution) * std::sqrt(p.kn)};
  }

  static void stored(const Params& p, EffectSet, const StoredState& s, Stored& out) {
    out.normal += 0.5 * p.kn * s.overlap * s.overlap;
    out.fn += p.kn * s.overlap;
  }
  static void rows(const Params& p, EffectSet e, const Inertia& m, Rows& out) {
    out.kn += p.kn;
    if (has(e, effect::normal_damping)) out.cn += 2.0 * damping_ratio(p.restitution) * std::sqrt(m.mass * p.kn);
  }

  // its dissipation: the normal force's non-elastic work (what its dashpot takes off F_n, and all of it
  // where F_n is clamped at 0 and no dashpot pushes)
  static constexpr std::array<std::string_view, 1> dissipates{"normal_damping"};
  static double normal_dashpot(const Coeffs& c, const ContactKinematics& k, EffectSet e) {
    return has(e, effect::normal_damping) ? c.damp * k.sqrt_m * k.vn : 0.0;
  }
  static void dissipated(const Params&, const Coeffs&, EffectSet, const ContactStep& s, double* out) {
    out[0] = s.normal_share;
  }

  template <EffectSet E>
  static ContactState apply(const Coeffs& c, const ContactKinematics k, ContactState s, EffectSet scene) {
    double fn = -c.kn * k.delta;
    if (applies<E>(scene, effect::normal_damping)) fn -= c.damp * k.sqrt_m * k.vn;
    s.f.fn = s.acts ? (fn > 0.0 ? fn : 0.0) : 0.0;
    s.load = s.f.fn;
    return s;
  }
};

}  // namespace dem2d
