// Rolling term (effect rolling_resistance): an incremental rolling spring
// k_r capped by mu_r times the load, and (effect rolling_damping) a dashpot
// c_r = 2 nu_r sqrt(I_eff k_r) beside it, their sum capped again:
//
//   S_r <- clamp(S_r - k_r spin dt, +-mu_r F_n),   M_r = clamp(S_r - c_r spin, +-mu_r F_n)
//
// The same spring-slider as the tangential term (contact/tangential.hpp),
// on the relative spin. It acts only while the surfaces touch.
#pragma once

#include <array>
#include <cmath>
#include <string_view>

#include "contact/law_terms.hpp"

namespace dem2d {

struct Rolling {
  static constexpr EffectSet effect = effect::rolling_resistance;

  struct Params {
    double rolling_friction = 0.0;       // mu_r (m): |M_r| <= mu_r F_n
    double rolling_stiffness = 0.0;      // k_r (N m/rad)
    double rolling_damping_ratio = 0.0;  // nu_r
  };
  static constexpr std::array<LawKey<Params>, 3> keys{{
      {"rolling_friction", &Params::rolling_friction, effect::rolling_resistance,
       {"rolling friction length mu_r", "m", Rule::non_negative}},
      {"rolling_stiffness", &Params::rolling_stiffness, effect::rolling_resistance,
       {"rolling stiffness k_r", "N m/rad", Rule::non_negative}},
      {"rolling_damping_ratio", &Params::rolling_damping_ratio, effect::rolling_damping,
       {"rolling damping ratio nu_r (c_r = 2 nu_r sqrt(I_eff k_r))", "", Rule::non_negative}},
  }};

  struct Coeffs {
    double kr_dt;   // k_r dt (N m s/rad)
    double mu_r;    // m
    double damp_r;  // 2 nu_r sqrt(k_r): c_r = damp_r * sqrt(I_eff)
  };
  static Coeffs coefficients(const Params& p, double dt) {
    return {p.rolling_stiffness * dt, p.rolling_friction, 2.0 * p.rolling_damping_ratio * std::sqrt(p.rolling_stiffness)};
  }

  static void stored(const Params& p, EffectSet, const StoredState& s, Stored& out) {
    if (p.rolling_stiffness > 0.0) out.rolling += 0.5 * s.mr * s.mr / p.rolling_stiffness;
  }
  static void rows(const Params& p, EffectSet e, const Inertia& m, Rows& out) {
    out.kr += p.rolling_stiffness;
    if (has(e, effect::rolling_damping))
      out.cr += 2.0 * p.rolling_damping_ratio * std::sqrt(m.inertia * p.rolling_stiffness);
  }

  // its dissipation: the dashpot's and the slider's, as the tangential term's
  static constexpr std::array<std::string_view, 2> dissipates{"rolling_damping", "rolling_slip"};
  static void dissipated(const Params& p, const Coeffs& c, EffectSet e, const ContactStep& s, double* out) {
    const SliderLoss l = slider_loss(s.mr, s.k.spin, s.spring_r, s.spring_r_prev, p.rolling_stiffness, c.kr_dt, s.dt);
    if (has(e, effect::rolling_damping)) out[0] = l.dashpot;
    out[1] = l.slip;
  }
  static void released(const Params& p, EffectSet e, const StoredState& before, double* out) {
    Stored u;
    stored(p, e, before, u);
    out[1] = u.rolling;
  }

  template <EffectSet E>
  static ContactState apply(const Coeffs& c, const ContactKinematics k, ContactState s, EffectSet scene) {
    const CappedSpring r = capped_spring(applies<E>(scene, effect::rolling_damping), *s.mr, -c.kr_dt * k.spin,
                                         c.damp_r * k.sqrt_i * k.spin, c.mu_r * s.load);
    s.f.mr = s.touch ? r.force : 0.0;
    *s.mr = s.touch ? r.spring : 0.0;
    return s;
  }
};

}  // namespace dem2d
