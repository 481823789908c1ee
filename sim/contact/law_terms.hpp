// The parts a contact law is made of. A law is a list of terms (sub-laws),
// applied in order to every candidate contact by the contact model
// (contact/contact_model.hpp); the list is LawTerms in contact/contact_law.hpp.
// A term is one struct in its own header (contact/normal.hpp is the shortest):
//
//   static constexpr EffectSet effect;   // compiled in only with this effect (0: always)
//   struct Params { double ... = default; };            // the scene's values (SI)
//   static constexpr std::array<LawKey<Params>, N> keys; // their [contact] keys, units, ranges
//   struct Coeffs { double ...; };                      // what one step uses
//   static Coeffs coefficients(const Params&, double dt);
//   template <EffectSet E>
//   static ContactState apply(const Coeffs&, ContactKinematics, ContactState, EffectSet scene);
// and, where it has them,
//   static double range(const Coeffs&);      // how far beyond touching it acts (m)
//   template <class Law> static std::optional<LawIssue> check(const Law&);  // conditions across terms
//   static void stored(const Params&, EffectSet, const StoredState&, Stored&);  // energy in its springs
//   static void rows(const Params&, EffectSet, const Inertia&, Rows&);       // stiffness, damping
//   static double pull(const Coeffs&, double delta);  // its pull in F_n: not a load on friction (N/m)
// The last three make the stored energy (the energy ledger, diagnostics),
// the stability limit (contact/stability.hpp) and the load that caps
// friction (the run file's `sliding` and `mu_star`, the friction stage)
// right for the term without edits elsewhere: each adds its share to what
// the list folds (contact/contact_law.hpp). A term without them stores no
// energy, adds no spring or dashpot, and pulls nothing.
//
// A term that dissipates declares where to, and how much:
//   static constexpr std::array<std::string_view, N> dissipates;  // its energy-ledger columns
//   static void dissipated(const Params&, const Coeffs&, EffectSet, const ContactStep&, double* out);
// with, where it has them,
//   static double normal_dashpot(const Coeffs&, const ContactKinematics&, EffectSet);  // its push along n (N/m)
//   static void released(const Params&, EffectSet, const StoredState&, double* out);   // a contact that opened
// `out` is its own columns, in the order declared (J/m over the step). The
// ledger's columns are the list's (run files: /series/energy/<column>,
// checkpoints, `dem2d inspect --schema`), and it checks the balance with
// them (engine/energy_ledger.hpp). The normal force's non-elastic work is
// shared among the terms with a normal dashpot in proportion to their pushes
// (exact while F_n is not clamped at 0); ContactStep::normal_share is the
// term's share.
//
// Parameter and coefficient names must be unique across terms (ContactLaw
// and LawCoefficients inherit every term's, so a clash does not compile).
// Within apply, `if (applies<E>(scene, ...))` tests an effect the term
// depends on: a constant in a kernel specialised for E (the code of an absent
// effect is dropped), the scene's set in the generic kernel (E ==
// effect::generic, core/effects.hpp). apply must be branch-free otherwise
// (selects), and takes and returns the
// contact by value (a loop-local whose address is taken stays in memory
// inside an `omp simd` loop), so that the loops over list slots vectorise.
//
// Sign conventions: delta < 0 is an overlap, n points from the partner to
// the grain, t = z x n.
#pragma once

#include <algorithm>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/effects.hpp"
#include "core/key_spec.hpp"

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

// The relative motion at a contact, written once for the kernels and the
// energy ledger: from the relative velocity rv (v_i - v_j; against a body,
// v_i less the body's surface velocity at the contact point), the unit normal
// n (towards i), the branch lengths a (centre to contact point, m) and the
// spins w (rad/s).
struct ContactMotion {
  double vn;    // rv.n (m/s)
  double vt;    // tangential velocity of i's contact point relative to the partner's, along t = z x n (m/s)
  double spin;  // relative spin (rad/s)
};

// between grains i and j
constexpr ContactMotion grain_pair_motion(double rvx, double rvy, double nx, double ny, double ai, double wi, double aj,
                                          double wj) {
  return {rvx * nx + rvy * ny, rvx * -ny + rvy * nx - (ai * wi + aj * wj), wi - wj};
}

// between grain i and a body's surface (its motion is in rv)
constexpr ContactMotion grain_body_motion(double rvx, double rvy, double nx, double ny, double a, double w) {
  return {rvx * nx + rvy * ny, rvx * -ny + rvy * nx - a * w, w};
}

// What the law gives: on i, in the contact frame; the partner gets the opposite.
struct ContactForce {
  double fn;  // normal force along n (N/m), > 0 pushes the grains apart
  double ft;  // tangential force along t (N/m)
  double mr;  // rolling moment on i (N)
};

// One contact while the terms are applied to it.
struct ContactState {
  bool acts;     // the loop found its gap below the law's range
  bool touch;    // the surfaces touch: springs act (= acts unless a term acts across a gap)
  double load;   // what presses the surfaces together (N/m): the base of the friction caps
  ContactForce f;
  double* ft;    // stored tangential spring (N/m), updated in place
  double* mr;    // stored rolling spring (N), updated in place
};

// A scene key of a term's parameter.
template <class Params>
struct LawKey {
  std::string_view key;   // in [contact] and [contact.wall]
  double Params::*field;
  EffectSet needs;        // the effect that uses it (0: always used)
  Num spec;
};

// A condition on the law as a whole that it breaks: the message, and the
// keys to name (the first of them the scene's table gives).
struct LawIssue {
  std::vector<std::string_view> keys;
  std::string message;
};

// A contact's stored state, as the contact lists and the run file keep it.
struct StoredState {
  double overlap;  // (m), > 0 touching
  double ft;       // tangential spring (N/m)
  double mr;       // rolling spring (N)
};

// What a contact's springs hold, by the three ways a contact moves: normal
// (the overlap), tangential (the tangential spring), rolling (the rolling
// spring). Terms add to it (`stored`).
struct Stored {
  double normal = 0.0, tangential = 0.0, rolling = 0.0;  // energy (J/m)
  double fn = 0.0;  // the conservative part of F_n (N/m): what the springs push with;
                    // the rest of F_n is dashpots' (the energy ledger's normal damping)
  double total() const { return normal + tangential + rolling; }
  Stored& operator+=(const Stored& o) {
    normal += o.normal, tangential += o.tangential, rolling += o.rolling, fn += o.fn;
    return *this;
  }
};

// A touching pair of grains, for the stability analysis: its effective mass
// (kg/m) and moment of inertia (kg m).
struct Inertia {
  double mass, inertia;
};

// The contact's springs and dashpots, linearised: stiffness k and damping c
// of its normal and tangential motion (N/m; N s/m per m of depth) and of its
// rolling (the rolling stiffness's unit; that per rad/s). Terms add to it
// (`rows`).
struct Rows {
  double kn = 0.0, kt = 0.0, kr = 0.0;
  double cn = 0.0, ct = 0.0, cr = 0.0;
};

// A touching contact over one step, as the energy ledger sees it after the
// force evaluation: what a term's `dissipated` reads.
struct ContactStep {
  ContactKinematics k;  // at the step's end (delta, vn, vt, spin, sqrt_m, sqrt_i)
  double dt;            // (s)
  double normal_share;  // the term's share of (Stored::fn - F_n) vn dt, the normal force's non-elastic work (J/m)
  double ft, spring_t, spring_t_prev;  // the tangential force on the grain; its spring now and at the start (N/m)
  double mr, spring_r, spring_r_prev;  // the rolling moment on the grain; its spring now and at the start (N)
};

// What a spring-slider with a dashpot beside it (capped_spring below)
// dissipated over a step: `force` acts on the grain at the step's end, `rate`
// is the relative motion its spring integrated (v_t or the relative spin),
// `spring`/`spring_prev` its stored value at the end and the start, k its
// stiffness. The slider takes what the cap cut from the spring,
// 1/2 (S_prev + S)(S_trial - S)/k (the return mapping, weighted as the ledger
// weighs the work: trapezoid); the dashpot the power of the force's
// non-spring part, -(F - S) rate dt. Both are >= 0 (docs/energy.md).
struct SliderLoss {
  double dashpot = 0.0, slip = 0.0;
};

inline SliderLoss slider_loss(double force, double rate, double spring, double spring_prev, double k, double k_dt,
                              double dt) {
  SliderLoss c;
  if (k > 0.0) {
    const double trial = spring_prev - k_dt * rate;
    c.slip = 0.5 * (spring_prev + spring) * (trial - spring) / k;
  }
  c.dashpot = -(force - spring) * rate * dt;
  return c;
}

template <class... Terms>
struct TermList {};

// Whether term T is compiled into the law for effect set E.
template <class T>
constexpr bool term_active(EffectSet e) {
  return T::effect == 0 || has(e, T::effect);
}

// An incremental spring capped at +-cap, with (damped) a dashpot beside it
// and their sum capped again: the tangential force and the rolling moment.
// `increment` is the spring's change this step (-k v dt), `dashpot` the
// dashpot's force c v.
struct CappedSpring {
  double force;   // what acts on the grain
  double spring;  // the spring stored for the next step
};

inline CappedSpring capped_spring(bool damped, double stored, double increment, double dashpot, double cap) {
  const double spring = std::clamp(stored + increment, -cap, cap);
  if (!damped) return {spring, spring};
  return {std::clamp(spring - dashpot, -cap, cap), spring};
}

}  // namespace dem2d
