// Opt-in physical effects. A scene names the set it needs; the engine runs a
// kernel instantiated for exactly that set where the build has one (see
// engine/kernels.hpp), so an absent effect is compiled out of the hot loop
// rather than tested per contact; any other valid set runs on the generic
// kernel, which tests the set at run time.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace dem2d {

using EffectSet = std::uint32_t;

namespace effect {
inline constexpr EffectSet gravity = 1u << 0;             // body force g on every grain
inline constexpr EffectSet normal_damping = 1u << 1;      // viscous normal term from the restitution e
inline constexpr EffectSet friction = 1u << 2;            // incremental tangential spring + Coulomb cap
inline constexpr EffectSet rolling_resistance = 1u << 3;  // incremental rolling spring + cap mu_r F_n
inline constexpr EffectSet walls = 1u << 4;               // grain / body contacts (bodies: shape/shape.hpp)
inline constexpr EffectSet moving_bodies = 1u << 5;       // kinematic bodies with a prescribed velocity or schedule
inline constexpr EffectSet tangential_damping = 1u << 6;  // dashpot beside the tangential spring (needs friction)
inline constexpr EffectSet rolling_damping = 1u << 7;     // dashpot beside the rolling spring (needs rolling_resistance)
inline constexpr EffectSet cohesion = 1u << 8;            // attraction up to a range beyond contact (contact/cohesion.hpp)
inline constexpr EffectSet rotating_bodies = 1u << 9;     // schedules that turn bodies about a pivot (core/motion.hpp)
inline constexpr int count = 10;
inline constexpr EffectSet all = (1u << count) - 1;
// Not a scene effect: the mark of the generic kernel, which has every term
// compiled in and applies the ones the scene's set names, tested at run time
// (engine/kernel_table.hpp).
inline constexpr EffectSet generic = 1u << 31;
}  // namespace effect

struct EffectName {
  EffectSet bit;
  std::string_view key;  // key in the scene's [effects] table
};

inline constexpr std::array<EffectName, effect::count> kEffectNames{{
    {effect::gravity, "gravity"},
    {effect::normal_damping, "normal_damping"},
    {effect::friction, "friction"},
    {effect::rolling_resistance, "rolling_resistance"},
    {effect::walls, "walls"},
    {effect::moving_bodies, "moving_bodies"},
    {effect::tangential_damping, "tangential_damping"},
    {effect::rolling_damping, "rolling_damping"},
    {effect::cohesion, "cohesion"},
    {effect::rotating_bodies, "rotating_bodies"},
}};

// Effects that only make sense on top of another: (effect, what it needs).
inline constexpr std::array<std::array<EffectSet, 2>, 4> kEffectNeeds{{
    {effect::tangential_damping, effect::friction},
    {effect::rolling_damping, effect::rolling_resistance},
    {effect::moving_bodies, effect::walls},
    {effect::rotating_bodies, effect::moving_bodies},
}};

constexpr bool has(EffectSet set, EffectSet bit) { return (set & bit) != 0; }

// Whether a kernel compiled for E applies effect `bit` to a scene whose set
// is `scene`. A specialised kernel's answer is fixed when it is compiled (a
// constant: the code of an absent effect is dropped); the generic kernel's
// is the scene's.
template <EffectSet E>
constexpr bool applies(EffectSet scene, EffectSet bit) {
  if constexpr (E == effect::generic)
    return has(scene, bit);
  else
    return has(E, bit);
}

// Whether a kernel compiled for E has the code of effect `bit` at all (for
// `if constexpr`, where a whole function is compiled in or out): a
// specialised kernel only for its own effects, the generic one for every one.
template <EffectSet E>
constexpr bool compiles(EffectSet bit) {
  return E == effect::generic || has(E, bit);
}

// A set the engine runs: known bits only, and every effect's prerequisite present.
constexpr bool is_valid(EffectSet set) {
  if (set > effect::all) return false;
  for (const auto& [bit, needs] : kEffectNeeds)
    if (has(set, bit) && !has(set, needs)) return false;
  return true;
}

// "gravity,friction,walls" (scene keys of the effects in the set, joined by sep).
inline std::string effect_names(EffectSet set, std::string_view sep = ",") {
  std::string out;
  for (const EffectName& e : kEffectNames) {
    if (!has(set, e.bit)) continue;
    if (!out.empty()) out.append(sep);
    out.append(e.key);
  }
  return out;
}

}  // namespace dem2d
