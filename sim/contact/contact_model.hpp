// The contact model: one object that both contact loops (grain-grain pairs
// and grain-body slots, engine/kernels.hpp) hand each candidate contact to.
// A loop knows the geometry (gap, normal, branch vectors) and the
// kinematics; the model knows the law: when a contact acts, and the normal
// force, tangential force and rolling moment it gives, updating the
// contact's stored springs. Sub-laws (normal spring and dashpot, tangential
// spring, rolling spring, their dashpots) are compiled in per effect set E
// with `if constexpr`, so an absent effect costs nothing; the model is a
// value (its coefficients) passed to the loop, inlined into it.
//
// Sign conventions as in contact_law.hpp: delta < 0 is an overlap, n points
// from the partner to the grain, t = z x n.
#pragma once

#include "contact/cohesion.hpp"
#include "contact/contact_law.hpp"
#include "core/effects.hpp"

namespace dem2d {

// One candidate contact as a loop sees it.
struct ContactKinematics {
  double delta;   // gap (m): centre distance minus the sum of radii, < 0 when overlapping
  double vn;      // (v_i - v_j).n (m/s)
  double vt;      // tangential velocity of i's contact point relative to the partner's (m/s); friction only
  double spin;    // omega_i - omega_j (rad/s); rolling resistance only
  double sqrt_m;  // sqrt(m_eff) (sqrt(kg/m))
  double sqrt_i;  // sqrt(I_eff) (sqrt(kg m)); rolling damping only
};

// What the law gives: on i, in the contact frame; the partner gets the opposite.
struct ContactForce {
  double fn;  // normal force along n (N/m), > 0 pushes the grains apart
  double ft;  // tangential force along t (N/m)
  double mr;  // rolling moment on i (N)
};

template <EffectSet E>
struct ContactModel {
  LawCoefficients c;

  // How far beyond touching (gap > 0) the law still acts (m): the loops
  // treat a candidate as acting when its gap is below this.
  double range() const {
    if constexpr (has(E, effect::cohesion))
      return c.coh_range;
    else
      return 0.0;
  }
  // The centre distance below which a pair with radii summing to rsum acts
  // (rsum itself without cohesion: no `+ 0.0` left for the compiler to keep).
  double reach(double rsum) const {
    if constexpr (has(E, effect::cohesion))
      return rsum + c.coh_range;
    else
      return rsum;
  }

  // The force of a candidate contact; `acts`: the loop found its gap below
  // range(). `ft` and `mr` are its stored tangential and rolling springs,
  // updated in place; they act only in contact (gap < 0) and are released
  // otherwise. Branch-free (selects), so that a loop over slots vectorises.
  ContactForce eval(const ContactKinematics& k, bool acts, double& ft, double& mr) const {
    // without cohesion a contact acts exactly when it touches (the loop's
    // test, kept as the loop computes it, bit for bit)
    bool touch = acts;
    ContactForce f{acts ? normal_force<E>(c, k.delta, k.vn, k.sqrt_m) : 0.0, 0.0, 0.0};
    double load = f.fn;  // what presses the surfaces together: the friction cap's base
    if constexpr (has(E, effect::cohesion)) {
      touch = acts && k.delta < 0.0;
      load = touch ? f.fn : 0.0;
      f.fn = acts ? load - cohesive_pull(c, k.delta) : 0.0;
    }
    if constexpr (has(E, effect::friction)) {
      const CappedSpring t = capped_spring<has(E, effect::tangential_damping)>(
          ft, -c.kt_dt * k.vt, c.damp_t * k.sqrt_m * k.vt, c.mu * load);
      f.ft = touch ? t.force : 0.0;
      ft = touch ? t.spring : 0.0;
    }
    if constexpr (has(E, effect::rolling_resistance)) {
      const CappedSpring r = capped_spring<has(E, effect::rolling_damping)>(
          mr, -c.kr_dt * k.spin, c.damp_r * k.sqrt_i * k.spin, c.mu_r * load);
      f.mr = touch ? r.force : 0.0;
      mr = touch ? r.spring : 0.0;
    }
    return f;
  }
};

// Whether a slot of the contact lists acted at its last evaluation, from the
// overlap it stored (-delta when acting, 0 otherwise): touching, or, with
// cohesion, attracting across a gap (a negative overlap).
inline bool acted(double overlap, bool cohesion) { return overlap > 0.0 || (cohesion && overlap < 0.0); }

}  // namespace dem2d
