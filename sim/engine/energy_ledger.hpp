// The energy ledger: where the energy of a run goes, step by step, so that
//   kinetic + elastic (normal, tangential, rolling) + gravity
//   + dissipated (one column per channel the contact law's terms declare:
//     normal damping, tangential damping, sliding, rolling damping, rolling
//     slip; contact/contact_law.hpp, kDissipationColumns)
//   + removed + integration error - work of the bodies
// stays equal to its value at the start (to round-off).
//
// How each term is measured (derivation: docs/energy.md):
// - The work of every contact on its grains over a step is the trapezoid
//   1/2 (F^n + F^(n+1)) . (relative displacement dt v^(n+1/2)) of the kernel's
//   own contact forces and torques; with velocity Verlet this is exactly the
//   change of the grains' "shadow" kinetic energy 1/2 m v^(n-1/2).v^(n+1/2).
// - What a contact receives goes into its springs (their energy change), what
//   its terms dissipate (each term says how much, into its own columns:
//   dashpots c v^2 dt, sliders the spring energy the caps cut off,
//   1/2 (S_trial^2 - S^2)/k), or is left over: that remainder, per
//   contact, is the integration error, with the difference between the
//   physical and the shadow kinetic energy. It vanishes as dt -> 0 (second
//   order for elastic contacts); it is not defined as what closes the balance.
// - A moving body's work is the trapezoid force on the grain times the body's
//   displacement v_b dt; gravity's is the change of -m g.x.
// - Grains that leave the domain and contacts of removed bodies take their
//   energy out of the scene: `removed`.
// Each thread adds its own grains' contacts into per-grain accumulators (the
// row owner's), summed in index order when read: the ledger is bitwise the
// same for any thread count. Off unless the scene asks for it
// (output.energy_balance): then the step runs two extra passes over the
// contacts and two extra barriers; off, it costs nothing.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>
#include <utility>

#include "contact/contact_law.hpp"
#include "core/aligned_vector.hpp"

namespace dem2d {

struct System;

struct EnergyLedger {
  bool on = false;
  // per grain (J/m): the contacts of its rows; each written only by the
  // thread that owns the grain
  AlignedVector<double> error, body_work;
  std::array<AlignedVector<double>, kDissipationColumns.size()> dissipated;  // by column
  double removed = 0.0;        // energy taken out with lost grains and removed bodies' contacts (J/m)
  double error_offset = 0.0;   // the integration error's part not kept per grain (J/m): its value
                               // at the start, less the energy of contacts removed with their grains or bodies

};

// The per-grain accumulators by name (checkpoints: energy/<name>); Ledger may be const.
template <class Ledger>
auto accumulators(Ledger& e) {
  std::array<std::pair<std::string_view, decltype(&e.error)>, kDissipationColumns.size() + 2> out;
  out[0] = {"error", &e.error};
  for (std::size_t k = 0; k < kDissipationColumns.size(); ++k) out[k + 1] = {kDissipationColumns[k], &e.dissipated[k]};
  out.back() = {"body_work", &e.body_work};
  return out;
}

// Every term of the balance at the current (full) step, in J/m.
struct EnergyBalance {
  double kinetic = 0.0;                                                   // 1/2 m v^2 + 1/2 I w^2
  double elastic_normal = 0.0, elastic_tangential = 0.0, elastic_rolling = 0.0;
  double gravity = 0.0;                                                   // -sum m g.x of the active grains
  double body_work = 0.0;                                                 // done on the grains by moving bodies
  Dissipation dissipated{};                                               // by column (kDissipationColumns)
  double removed = 0.0;
  double integration_error = 0.0;
  // The terms by name (run files: /series/energy/<name>), in this order.
  static constexpr std::size_t kTerms = 8 + kDissipationColumns.size();
  std::array<std::pair<std::string_view, double>, kTerms> terms() const {
    std::array<std::pair<std::string_view, double>, kTerms> out;
    std::size_t k = 0;
    for (const auto& term : {std::pair<std::string_view, double>{"kinetic", kinetic}, {"elastic_normal", elastic_normal},
                             {"elastic_tangential", elastic_tangential}, {"elastic_rolling", elastic_rolling},
                             {"gravity", gravity}, {"body_work", body_work}})
      out[k++] = term;
    for (std::size_t c = 0; c < dissipated.size(); ++c) out[k++] = {kDissipationColumns[c], dissipated[c]};
    out[k++] = {"removed", removed};
    out[k++] = {"integration_error", integration_error};
    return out;
  }
  // The dissipation column with this name (0 if the law has none by it).
  double dissipated_in(std::string_view column) const {
    for (std::size_t c = 0; c < dissipated.size(); ++c)
      if (kDissipationColumns[c] == column) return dissipated[c];
    return 0.0;
  }
  // How a term enters the conserved total: -1 for the work done on the grains
  // from outside (body_work), +1 for every other. The schema exports it
  // (dem2d inspect --schema: energy_balance), the checkers sum by it.
  static constexpr int sign_of(std::string_view term) { return term == "body_work" ? -1 : 1; }
  // sum of sign_of(term) x term: constant over a run (to round-off)
  double total() const {
    double sum = 0.0;
    for (const auto& [term, value] : terms()) sum += sign_of(term) * value;
    return sum;
  }
};

namespace energy {

// Starts the ledger at the current state (all accumulated terms zero).
void start(System& s);
// This thread's share of a step's first half: the contacts' work with the
// forces of the step's start over this step's displacements, and their
// stored energy then. After the drift and a barrier, before any rebuild.
void open_step(System& s);
// This thread's share of the second half: the same with the new forces,
// their stored energy and what the dashpots and caps dissipated. After the
// force evaluation and a barrier; a barrier must follow.
void close_step(System& s);
// Grain i leaves the scene after this step's drift (before its removal).
void remove_grain(System& s, std::size_t i);
// The terms at the current step (serial, index order).
EnergyBalance balance(const System& s);

}  // namespace energy

}  // namespace dem2d
