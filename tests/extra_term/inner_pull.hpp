// A contact term that exists only in this test build: the proof that a term
// owns all of its physics. Inside the overlap it pulls the surfaces together
// with a linear spring of stiffness k_a < k_n (a crude liquid-bridge or
// adhesive layer), so that
//
//   F_n = (k_n - k_a) overlap,   the load that caps friction  k_n overlap,
//   stored energy  1/2 (k_n - k_a) overlap^2,   normal stiffness  k_n - k_a.
//
// It is written as a new term would be (sim/contact/law_terms.hpp): its own
// header, its line in the law's list (law_list.hpp here) and its effect's
// line in the effect list (effects.hpp here). The stability limit,
// the energy ledger and the run file's mu_star and sliding must then be
// right for it with no other edit; test_extra_term.cpp checks all three.
#pragma once

#include <array>

#include "contact/law_terms.hpp"

namespace dem2d {

struct InnerPull {
  static constexpr EffectSet effect = effect::inner_pull;  // its line in the effect list: effects.hpp here

  struct Params {
    double inner_pull = 0.0;  // k_a (N/m)
  };
  static constexpr std::array<LawKey<Params>, 1> keys{{
      {"inner_pull", &Params::inner_pull, 0, {"pull stiffness k_a inside the overlap", "N/m", Rule::non_negative}},
  }};

  struct Coeffs {
    double ka;  // N/m
  };
  static Coeffs coefficients(const Params& p, double /*dt*/) { return {p.inner_pull}; }

  static void stored(const Params& p, EffectSet, const StoredState& s, Stored& out) {
    out.normal -= 0.5 * p.inner_pull * s.overlap * s.overlap;
    out.fn -= p.inner_pull * s.overlap;
  }
  static void rows(const Params& p, EffectSet, const Inertia&, Rows& out) { out.kn -= p.inner_pull; }
  static double pull(const Coeffs& c, double delta) { return -c.ka * delta; }

  template <EffectSet E>
  static ContactState apply(const Coeffs& c, const ContactKinematics k, ContactState s, EffectSet /*scene*/) {
    s.f.fn -= s.touch ? pull(c, k.delta) : 0.0;
    return s;
  }
};

}  // namespace dem2d
