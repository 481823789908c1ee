// A contact term that exists only in this test build: the proof that a term
// owns all of its physics. Inside the overlap it pulls the surfaces together
// with a linear spring of stiffness k_a < k_n and a dashpot c_a (a crude
// viscous liquid-bridge or adhesive layer), so that, with x the overlap,
//
//   F_n = (k_n - k_a) x - c_a vn   (without the normal dashpot: a linear
//                                   spring-dashpot that may pull),
//   the load that caps friction  k_n x,   stored energy  1/2 (k_n - k_a) x^2,
//   normal stiffness  k_n - k_a,   dissipated  c_a vn^2 dt per step, into the
//   energy ledger's column inner_pull_damping.
//
// It is written as a new term would be (sim/contact/law_terms.hpp): its own
// header, its line in the law's list (law_list.hpp here) and its effect's
// line in the effect list (effects.hpp here). The stability limit, the
// energy ledger (its stored energy and its own dissipation column) and the
// run file's mu_star and sliding must then be right for it with no other
// edit; test_extra_term.cpp checks them.
#pragma once

#include <array>
#include <string_view>

#include "contact/law_terms.hpp"

namespace dem2d {

struct InnerPull {
  static constexpr EffectSet effect = effect::inner_pull;  // its line in the effect list: effects.hpp here

  struct Params {
    double inner_pull = 0.0;          // k_a (N/m)
    double inner_pull_damping = 0.0;  // c_a (N s/m^2: N/m per m/s)
  };
  static constexpr std::array<LawKey<Params>, 2> keys{{
      {"inner_pull", &Params::inner_pull, 0, {"pull stiffness k_a inside the overlap", "N/m", Rule::non_negative}},
      {"inner_pull_damping", &Params::inner_pull_damping, 0,
       {"damping c_a of the pull inside the overlap", "N s/m^2", Rule::non_negative}},
  }};

  struct Coeffs {
    double ka;  // N/m
    double ca;  // N s/m^2
  };
  static Coeffs coefficients(const Params& p, double /*dt*/) { return {p.inner_pull, p.inner_pull_damping}; }

  static void stored(const Params& p, EffectSet, const StoredState& s, Stored& out) {
    out.normal -= 0.5 * p.inner_pull * s.overlap * s.overlap;
    out.fn -= p.inner_pull * s.overlap;
  }
  static void rows(const Params& p, EffectSet, const Inertia&, Rows& out) {
    out.kn -= p.inner_pull;
    out.cn += p.inner_pull_damping;
  }
  static double pull(const Coeffs& c, double delta) { return -c.ka * delta; }

  // its dissipation: its dashpot's share of the normal force's non-elastic work
  static constexpr std::array<std::string_view, 1> dissipates{"inner_pull_damping"};
  static double normal_dashpot(const Coeffs& c, const ContactKinematics& k, EffectSet) { return c.ca * k.vn; }
  static void dissipated(const Params&, const Coeffs&, EffectSet, const ContactStep& s, double* out) {
    out[0] = s.normal_share;
  }

  template <EffectSet E>
  static ContactState apply(const Coeffs& c, const ContactKinematics k, ContactState s, EffectSet /*scene*/) {
    s.f.fn -= s.touch ? pull(c, k.delta) + c.ca * k.vn : 0.0;
    return s;
  }
};

}  // namespace dem2d
