// The effect sets the kernels are specialised for (engine/kernel_sets.inc,
// or every valid set in a build with -DDEM2D_KERNEL_SETS=all); any other
// valid set runs on the generic kernel (engine/kernel_table.hpp).
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "core/effects.hpp"

namespace dem2d {

// "gravity,friction" -> its bits; nullopt if a name is not an effect (or
// repeats). "" is the empty set. Order does not matter.
constexpr std::optional<EffectSet> parse_effect_set(std::string_view names) {
  EffectSet set = 0;
  while (!names.empty()) {
    const std::size_t comma = names.find(',');
    const std::string_view name = names.substr(0, comma);
    EffectSet bit = 0;
    for (const EffectName& e : kEffectNames)
      if (e.key == name) bit = e.bit;
    if (bit == 0 || has(set, bit)) return std::nullopt;
    set |= bit;
    if (comma == std::string_view::npos) break;
    names.remove_prefix(comma + 1);
    if (names.empty()) return std::nullopt;  // a trailing comma
  }
  return set;
}

// Whether this build has kernels specialised for `effects`.
bool kernels_specialised(EffectSet effects);

// Which kernel runs a scene with (valid) `effects`, in words for a log
// (`generic`: the generic one asked for, Scene::generic_kernel).
std::string kernel_description(EffectSet effects, bool generic = false);

}  // namespace dem2d
