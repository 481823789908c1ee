// The contact law (SPEC "Contact model"), shared by particle-particle and
// particle-body contacts: the list of its terms, applied in this order to
// every candidate contact (contact/law_terms.hpp says what a term is).
//
//   normal      F_n = max(0, -k_n delta - c_n vn)             contact/normal.hpp
//   cohesion    F_n -= pull(delta), in range beyond contact   contact/cohesion.hpp
//   tangential  spring-slider, cap mu F_n                     contact/tangential.hpp
//   rolling     rolling spring-slider, cap mu_r F_n           contact/rolling.hpp
//
// A new term is its own header plus its line here (and its effect in
// core/effects.hpp); the scene reader, the coefficients and the model take
// it from this list.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "contact/cohesion.hpp"
#include "contact/law_terms.hpp"
#include "contact/normal.hpp"
#include "contact/rolling.hpp"
#include "contact/tangential.hpp"
#include "core/effects.hpp"

namespace dem2d {

using LawTerms = TermList<NormalLaw, Cohesion, Tangential, Rolling>;

template <class... T>
struct AllParams : T::Params... {};
template <class... T>
struct AllCoeffs : T::Coeffs... {};
template <template <class...> class All, class List>
struct Gather;
template <template <class...> class All, class... T>
struct Gather<All, TermList<T...>> {
  using type = All<T...>;
};

// Material constants of one contact law as the scene gives them (SI): every
// term's Params.
struct ContactLaw : Gather<AllParams, LawTerms>::type {};

// The law with the per-step products folded in, as the kernel uses it:
// every term's Coeffs.
struct LawCoefficients : Gather<AllCoeffs, LawTerms>::type {};

template <class... T>
LawCoefficients coefficients_of(TermList<T...>, const ContactLaw& law, double dt) {
  LawCoefficients c;
  ((static_cast<typename T::Coeffs&>(c) = T::coefficients(law, dt)), ...);
  return c;
}
inline LawCoefficients coefficients(const ContactLaw& law, double dt) { return coefficients_of(LawTerms{}, law, dt); }

// Every term's scene keys, in the list's order.
template <class... T>
std::vector<LawKey<ContactLaw>> law_keys_of(TermList<T...>) {
  std::vector<LawKey<ContactLaw>> all;
  (
      [&] {
        for (const auto& k : T::keys) all.push_back({k.key, k.field, k.needs, k.spec});
      }(),
      ...);
  return all;
}
inline const std::vector<LawKey<ContactLaw>>& contact_law_keys() {
  static const std::vector<LawKey<ContactLaw>> keys = law_keys_of(LawTerms{});
  return keys;
}

// The conditions across terms that `law` breaks under `effects`, from the
// terms compiled in for them.
template <class... T>
std::vector<LawIssue> law_issues_of(TermList<T...>, const ContactLaw& law, EffectSet effects) {
  std::vector<LawIssue> issues;
  (
      [&] {
        if constexpr (requires { T::check(law); })
          if (term_active<T>(effects))
            if (auto issue = T::check(law)) issues.push_back(std::move(*issue));
      }(),
      ...);
  return issues;
}
inline std::vector<LawIssue> law_issues(const ContactLaw& law, EffectSet effects) {
  return law_issues_of(LawTerms{}, law, effects);
}

// Whether the law for `effects` acts across a gap (a term with a range):
// then the neighbour search reaches further and a list slot with a negative
// overlap acted.
template <class... T>
constexpr bool reaches_beyond_of(TermList<T...>, EffectSet effects) {
  return ((term_active<T>(effects) && requires(const typename T::Coeffs& x) { T::range(x); }) || ...);
}
constexpr bool reaches_beyond_contact(EffectSet effects) { return reaches_beyond_of(LawTerms{}, effects); }

// How far beyond touching (gap > 0) the law for `effects` acts (m): the
// largest range of its terms, 0 if none has one.
template <class... T>
double range_of(TermList<T...>, const LawCoefficients& c, EffectSet effects) {
  double r = 0.0;
  (
      [&] {
        if constexpr (requires(const typename T::Coeffs& x) { T::range(x); })
          if (term_active<T>(effects)) r = std::max(r, T::range(c));
      }(),
      ...);
  return r;
}
inline double law_range(const LawCoefficients& c, EffectSet effects) { return range_of(LawTerms{}, c, effects); }

// Energy stored in one contact's springs (J/m): 1/2 k_n overlap^2, 1/2 S_t^2/k_t
// and 1/2 S_r^2/k_r, the last two only with the effects that add the springs.
struct SpringEnergy {
  double normal = 0.0, tangential = 0.0, rolling = 0.0;
  double total() const { return normal + tangential + rolling; }
};

inline SpringEnergy spring_energy(const ContactLaw& law, EffectSet effects, double overlap, double ft, double mr) {
  SpringEnergy u;
  u.normal = 0.5 * law.kn * overlap * overlap;
  if (has(effects, effect::friction) && law.kt > 0.0) u.tangential = 0.5 * ft * ft / law.kt;
  if (has(effects, effect::rolling_resistance) && law.rolling_stiffness > 0.0)
    u.rolling = 0.5 * mr * mr / law.rolling_stiffness;
  return u;
}

// The slip state as the run file reports it: the tangential force sits on the cone.
inline bool is_sliding(double fn, double ft, double mu) { return fn > 0.0 && std::abs(ft) >= mu * fn; }

}  // namespace dem2d
