// Tangential term (effect friction): an incremental spring k_t capped by
// Coulomb's mu times the load, and (effect tangential_damping) a dashpot
// c_t = 2 nu_t sqrt(m_eff k_t) beside it, their sum capped again:
//
//   S_t <- clamp(S_t - k_t vt dt, +-mu F_n),   F_t = clamp(S_t - c_t vt, +-mu F_n)
//
// Without the dashpot F_t = S_t: the paper's law. This differs from LAMMPS's
// granular models and MercuryDPM, which while sliding reset the spring to
// S = F_cap + c v: that can load the spring beyond the cap (c v > mu F_n)
// and hand the energy back to the grains later (the energy ledger measured
// negative slip dissipation on a single oblique collision). Here the
// spring-slider and the dashpot each dissipate >= 0 at every step
// (docs/contact_law.md).
//
// In 2D the tangent direction is unique, so the stored spring is a scalar
// along the current t: it turns with the contact, keeping its magnitude,
// which is exactly "kept in the current tangent direction". It acts only
// while the surfaces touch and is released otherwise.
#pragma once

#include <array>
#include <cmath>
#include <string_view>

#include "contact/law_terms.hpp"

namespace dem2d {

struct Tangential {
  static constexpr EffectSet effect = effect::friction;

  struct Params {
    double kt = 0.0;                        // tangential stiffness (N/m)
    double friction = 0.0;                  // Coulomb coefficient mu
    double tangential_damping_ratio = 0.0;  // nu_t
  };
  static constexpr std::array<LawKey<Params>, 3> keys{{
      {"kt", &Params::kt, effect::friction, {"tangential stiffness", "N/m", Rule::non_negative}},
      {"friction", &Params::friction, effect::friction, {"Coulomb friction coefficient mu", "", Rule::non_negative}},
      {"tangential_damping_ratio", &Params::tangential_damping_ratio, effect::tangential_damping,
       {"tangential damping ratio nu_t (c_t = 2 nu_t sqrt(m_eff k_t))", "", Rule::non_negative}},
  }};

  struct Coeffs {
    double kt_dt;   // k_t dt (N s/m)
    double mu;      // -
    double damp_t;  // 2 nu_t sqrt(k_t): c_t = damp_t * sqrt(m_eff)
  };
  static Coeffs coefficients(const Params& p, double dt) {
    return {p.kt * dt, p.friction, 2.0 * p.tangential_damping_ratio * std::sqrt(p.kt)};
  }

  static void stored(const Params& p, EffectSet, const StoredState& s, Stored& out) {
    if (p.kt > 0.0) out.tangential += 0.5 * s.ft * s.ft / p.kt;
  }
  static void rows(const Params& p, EffectSet e, const Inertia& m, Rows& out) {
    out.kt += p.kt;
    if (has(e, effect::tangential_damping)) out.ct += 2.0 * p.tangential_damping_ratio * std::sqrt(m.mass * p.kt);
  }

  // its dissipation: the dashpot's and the slider's (slider_loss); a contact that opens hands its spring's
  // energy to the slider
  static constexpr std::array<std::string_view, 2> dissipates{"tangential_damping", "sliding"};
  static void dissipated(const Params& p, const Coeffs& c, EffectSet e, const ContactStep& s, double* out) {
    const SliderLoss l = slider_loss(s.ft, s.k.vt, s.spring_t, s.spring_t_prev, p.kt, c.kt_dt, s.dt);
    if (has(e, effect::tangential_damping)) out[0] = l.dashpot;
    out[1] = l.slip;
  }
  static void released(const Params& p, EffectSet e, const StoredState& before, double* out) {
    Stored u;
    stored(p, e, before, u);
    out[1] = u.tangential;
  }

  template <EffectSet E>
  static ContactState apply(const Coeffs& c, const ContactKinematics k, ContactState s, EffectSet scene) {
    const CappedSpring t = capped_spring(applies<E>(scene, effect::tangential_damping), *s.ft, -c.kt_dt * k.vt,
                                         c.damp_t * k.sqrt_m * k.vt, c.mu * s.load);
    s.f.ft = s.touch ? t.force : 0.0;
    *s.ft = s.touch ? t.spring : 0.0;
    return s;
  }
};

}  // namespace dem2d
