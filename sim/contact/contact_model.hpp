// The contact model: one object that both contact loops (grain-grain pairs
// and grain-body slots, engine/kernels.hpp) hand each candidate contact to.
// A loop knows the geometry (gap, normal, branch vectors) and the
// kinematics; the model knows the law: when a contact acts, and the normal
// force, tangential force and rolling moment it gives, updating the
// contact's stored springs. It applies the law's terms (LawTerms,
// contact/contact_law.hpp) in order, each compiled in only for the effect
// sets that name it (`if constexpr`), so an absent effect costs nothing; the
// model is a value (its coefficients) passed to the loop, inlined into it.
// The generic model (E == effect::generic) has every term compiled in and
// applies those of the scene's set, tested at run time: a term it skips
// leaves no trace, so its forces are the specialised model's bit for bit.
#pragma once

#include "contact/contact_law.hpp"
#include "contact/law_terms.hpp"
#include "core/effects.hpp"

namespace dem2d {

template <EffectSet E>
struct ContactModel {
  LawCoefficients c;
  EffectSet scene = E;  // the scene's effects: what the generic model applies

  // The effects the model applies.
  EffectSet effects() const { return E == effect::generic ? scene : E; }
  // How far beyond touching (gap > 0) the law still acts (m): the loops
  // treat a candidate as acting when its gap is below this.
  double range() const { return law_range(c, effects()); }
  // The centre distance below which a pair with radii summing to rsum acts
  // (rsum itself when no term reaches beyond contact: no `+ 0.0` left for
  // the compiler to keep; the generic model's rsum + 0.0 is rsum too).
  double reach(double rsum) const {
    if constexpr (E == effect::generic || reaches_beyond_contact(E))
      return rsum + range();
    else
      return rsum;
  }

  // The force of a candidate contact; `acts`: the loop found its gap below
  // range(). `ft` and `mr` are its stored tangential and rolling springs,
  // updated in place; they act only in contact (gap < 0) and are released
  // otherwise. Branch-free (selects), so that a loop over slots vectorises.
  ContactForce eval(const ContactKinematics k, bool acts, double& ft, double& mr) const {
    return apply_all(LawTerms{}, k, ContactState{acts, acts, 0.0, {0.0, 0.0, 0.0}, &ft, &mr}).f;
  }

 private:
  template <class... T>
  ContactState apply_all(TermList<T...>, const ContactKinematics k, ContactState s) const {
    ((s = apply_one<T>(k, s)), ...);
    return s;
  }
  template <class T>
  ContactState apply_one(const ContactKinematics k, const ContactState s) const {
    if constexpr (E == effect::generic)
      return term_active<T>(scene) ? T::template apply<E>(c, k, s, scene) : s;
    else if constexpr (term_active<T>(E))
      return T::template apply<E>(c, k, s, scene);
    else
      return s;
  }
};

// Whether a slot of the contact lists acted at its last evaluation, from the
// overlap it stored (-delta when acting, 0 otherwise): touching, or, for a
// law that reaches beyond contact (reaches_beyond_contact), acting across a
// gap (a negative overlap).
inline bool acted(double overlap, bool across_gaps) { return overlap > 0.0 || (across_gaps && overlap < 0.0); }

}  // namespace dem2d
