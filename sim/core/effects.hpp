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

// The effects, once: X(key, what it needs or none, what it does). An
// effect's bit is its place in this list; its key is the scene's [effects]
// key, the run file's and `dem2d --list-effects`'. A new contact term with
// an effect of its own adds its line here (a build that tests the term
// contract adds its own through DEM2D_EXTRA_EFFECTS_HEADER, tests/extra_term/).
#define DEM2D_EFFECTS(X)                                                                            \
  X(gravity, none, "body force g on every grain")                                                   \
  X(normal_damping, none, "viscous normal term from the restitution e")                             \
  X(friction, none, "incremental tangential spring + Coulomb cap")                                  \
  X(rolling_resistance, none, "incremental rolling spring + cap mu_r F_n")                          \
  X(walls, none, "grain / body contacts (bodies: shape/shape.hpp)")                                 \
  X(moving_bodies, walls, "kinematic bodies with a prescribed velocity or schedule")                \
  X(tangential_damping, friction, "dashpot beside the tangential spring")                           \
  X(rolling_damping, rolling_resistance, "dashpot beside the rolling spring")                       \
  X(cohesion, none, "attraction up to a range beyond contact (contact/cohesion.hpp)")               \
  X(rotating_bodies, moving_bodies, "schedules that turn bodies about a pivot (core/motion.hpp)")

#ifdef DEM2D_EXTRA_EFFECTS_HEADER
#include DEM2D_EXTRA_EFFECTS_HEADER  // defines DEM2D_EXTRA_EFFECTS(X), lines as above
#else
#define DEM2D_EXTRA_EFFECTS(X)
#endif
#define DEM2D_ALL_EFFECTS(X) DEM2D_EFFECTS(X) DEM2D_EXTRA_EFFECTS(X)

namespace effect {
// the place of each effect in the list
enum Place : int {
#define DEM2D_EFFECT_PLACE(key, needs, what) key##_place,
  DEM2D_ALL_EFFECTS(DEM2D_EFFECT_PLACE)
#undef DEM2D_EFFECT_PLACE
  count_place
};
inline constexpr EffectSet none = 0;
#define DEM2D_EFFECT_BIT(key, needs, what) inline constexpr EffectSet key = 1u << key##_place;
DEM2D_ALL_EFFECTS(DEM2D_EFFECT_BIT)
#undef DEM2D_EFFECT_BIT
inline constexpr int count = count_place;
static_assert(count <= 31, "bit 31 marks the generic kernel");
inline constexpr EffectSet all = (1u << count) - 1;
// Not a scene effect: the mark of the generic kernel, which has every term
// compiled in and applies the ones the scene's set names, tested at run time
// (engine/kernel_table.hpp).
inline constexpr EffectSet generic = 1u << 31;
}  // namespace effect

struct EffectName {
  EffectSet bit;
  std::string_view key;   // key in the scene's [effects] table
  EffectSet needs;        // the effect it only makes sense on top of (0: none)
  std::string_view what;  // what it does, in words
};

inline constexpr std::array<EffectName, effect::count> kEffectNames{{
#define DEM2D_EFFECT_NAME(key, needs, what) {effect::key, #key, effect::needs, what},
    DEM2D_ALL_EFFECTS(DEM2D_EFFECT_NAME)
#undef DEM2D_EFFECT_NAME
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
  for (const EffectName& e : kEffectNames)
    if (has(set, e.bit) && e.needs != 0 && !has(set, e.needs)) return false;
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
