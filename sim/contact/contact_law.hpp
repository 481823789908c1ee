// The contact law (docs/paper.md, "Contact model"), shared by particle-particle and
// particle-body contacts: the list of its terms, applied in this order to
// every candidate contact (contact/law_terms.hpp says what a term is).
//
//   normal      F_n = max(0, -k_n delta - c_n vn)             contact/normal.hpp
//   cohesion    F_n -= pull(delta), in range beyond contact   contact/cohesion.hpp
//   tangential  spring-slider, cap mu F_n                     contact/tangential.hpp
//   rolling     rolling spring-slider, cap mu_r F_n           contact/rolling.hpp
//
// A new term is its own header plus its line here (and its effect's line in
// core/effects.hpp's DEM2D_EFFECTS); the scene reader, the coefficients, the model, the
// stored energy, the stability limit and the load that caps friction take
// it from this list.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "contact/cohesion.hpp"
#include "contact/law_terms.hpp"
#include "contact/normal.hpp"
#include "contact/rolling.hpp"
#include "contact/tangential.hpp"
#include "core/effects.hpp"

#ifdef DEM2D_LAW_TERMS_HEADER
#include DEM2D_LAW_TERMS_HEADER  // another list, for a build that tests the term contract (tests/extra_term/)
#else
namespace dem2d {
using LawTerms = TermList<NormalLaw, Cohesion, Tangential, Rolling>;
}  // namespace dem2d
#endif

namespace dem2d {

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

// Calls f.template operator()<T>() for every term T of the law compiled in
// for `effects`, in the list's order: the folds below are written with it.
template <class F, class... T>
void for_each_term_of(TermList<T...>, EffectSet effects, F&& f) {
  ((term_active<T>(effects) ? f.template operator()<T>() : void()), ...);
}
template <class F>
void for_each_term(EffectSet effects, F&& f) {
  for_each_term_of(LawTerms{}, effects, std::forward<F>(f));
}

// The conditions across terms that `law` breaks under `effects`.
inline std::vector<LawIssue> law_issues(const ContactLaw& law, EffectSet effects) {
  std::vector<LawIssue> issues;
  for_each_term(effects, [&]<class T>() {
    if constexpr (requires { T::check(law); })
      if (auto issue = T::check(law)) issues.push_back(std::move(*issue));
  });
  return issues;
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
inline double law_range(const LawCoefficients& c, EffectSet effects) {
  double r = 0.0;
  for_each_term(effects, [&]<class T>() {
    if constexpr (requires { T::range(c); }) r = std::max(r, T::range(c));
  });
  return r;
}

// What one contact's springs hold (J/m, and the conservative part of F_n),
// from every term compiled in for `effects` that stores energy.
inline Stored spring_energy(const ContactLaw& law, EffectSet effects, double overlap, double ft, double mr) {
  const StoredState state{overlap, ft, mr};
  Stored out;
  for_each_term(effects, [&]<class T>() {
    if constexpr (requires { T::stored(law, effects, state, out); }) T::stored(law, effects, state, out);
  });
  return out;
}

// The springs and dashpots of a touching pair with this effective mass and
// inertia, from every term compiled in for `effects` (contact/stability.hpp).
inline Rows contact_rows(const ContactLaw& law, EffectSet effects, const Inertia& m) {
  Rows out;
  for_each_term(effects, [&]<class T>() {
    if constexpr (requires { T::rows(law, effects, m, out); }) T::rows(law, effects, m, out);
  });
  return out;
}

// The load that presses a contact's surfaces together and caps its friction
// (N/m): F_n plus what the terms compiled in for `effects` pull with, for a
// touching contact (overlap > 0, m); F_n otherwise.
inline double friction_load(const LawCoefficients& c, EffectSet effects, double fn, double overlap) {
  double load = fn;
  if (!(overlap > 0.0)) return load;
  for_each_term(effects, [&]<class T>() {
    if constexpr (requires { T::pull(c, -overlap); }) load += T::pull(c, -overlap);
  });
  return load;
}

// The energy ledger's dissipation columns: every term's (`dissipates`), in
// the list's order, whatever the effects (engine/energy_ledger.hpp).
template <class T>
constexpr std::size_t dissipation_count() {
  if constexpr (requires { T::dissipates; }) return T::dissipates.size();
  else return 0;
}
template <class... T>
constexpr auto dissipation_columns_of(TermList<T...>) {
  std::array<std::string_view, (dissipation_count<T>() + ... + 0)> out{};
  std::size_t k = 0;
  (
      [&] {
        if constexpr (requires { T::dissipates; })
          for (const std::string_view column : T::dissipates) out[k++] = column;
      }(),
      ...);
  return out;
}
inline constexpr auto kDissipationColumns = dissipation_columns_of(LawTerms{});
using Dissipation = std::array<double, kDissipationColumns.size()>;  // J/m, by column

// What the terms compiled in for `effects` dissipated at one touching contact
// over a step, by column. `normal_work`: the normal force's non-elastic work,
// (Stored::fn - F_n) vn dt, shared among the terms with a normal dashpot in
// proportion to what each takes off F_n (the first of them takes it all
// where none does: F_n clamped at 0).
template <class... T>
Dissipation dissipated_of(TermList<T...>, const ContactLaw& law, const LawCoefficients& c, EffectSet effects,
                          ContactStep s, double normal_work) {
  double dashpots = 0.0;
  for_each_term_of(TermList<T...>{}, effects, [&]<class U>() {
    if constexpr (requires { U::normal_dashpot(c, s.k, effects); }) dashpots += U::normal_dashpot(c, s.k, effects);
  });
  Dissipation out{};
  std::size_t column = 0;
  bool taken = false;
  (
      [&] {
        if constexpr (requires { T::dissipates; }) {
          if (term_active<T>(effects)) {
            s.normal_share = 0.0;
            if constexpr (requires { T::normal_dashpot(c, s.k, effects); }) {
              const double own = T::normal_dashpot(c, s.k, effects);
              s.normal_share = dashpots == 0.0 ? (taken ? 0.0 : normal_work)
                               : own == dashpots ? normal_work
                                                 : normal_work * (own / dashpots);
              taken = true;
            }
            T::dissipated(law, c, effects, s, &out[column]);
          }
          column += T::dissipates.size();
        }
      }(),
      ...);
  return out;
}
inline Dissipation dissipated(const ContactLaw& law, const LawCoefficients& c, EffectSet effects, const ContactStep& s,
                              double normal_work) {
  return dissipated_of(LawTerms{}, law, c, effects, s, normal_work);
}

// A contact that opened this step: what its springs held (`before`) goes to
// the columns of the terms that release it (their sliders), by column.
template <class... T>
Dissipation released_of(TermList<T...>, const ContactLaw& law, EffectSet effects, const StoredState& before) {
  Dissipation out{};
  std::size_t column = 0;
  (
      [&] {
        if constexpr (requires { T::dissipates; }) {
          if constexpr (requires { T::released(law, effects, before, &out[column]); })
            if (term_active<T>(effects)) T::released(law, effects, before, &out[column]);
          column += T::dissipates.size();
        }
      }(),
      ...);
  return out;
}
inline Dissipation released(const ContactLaw& law, EffectSet effects, const StoredState& before) {
  return released_of(LawTerms{}, law, effects, before);
}

// The slip state as the run file reports it: the tangential force sits on the cone.
inline bool is_sliding(double fn, double ft, double mu) { return fn > 0.0 && std::abs(ft) >= mu * fn; }

}  // namespace dem2d
