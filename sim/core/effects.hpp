// Opt-in physical effects. A scene names the set it needs; the engine runs a
// kernel instantiated for exactly that set (see engine/kernels.hpp), so an
// absent effect is compiled out of the hot loop rather than tested per contact.
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
inline constexpr EffectSet walls = 1u << 4;               // grain / sphero-line contacts
inline constexpr EffectSet moving_bodies = 1u << 5;       // kinematic sphero-lines with a prescribed velocity
inline constexpr int count = 6;
inline constexpr EffectSet all = (1u << count) - 1;
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
}};

constexpr bool has(EffectSet set, EffectSet bit) { return (set & bit) != 0; }

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
