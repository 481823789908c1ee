// The effect sets the kernels are compiled for (engine/kernel_sets.inc, or
// every valid set in a build with -DDEM2D_KERNEL_SETS=all): a scene's set
// must be one of them.
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

// Whether this build has the kernels of `effects`.
bool kernels_compiled(EffectSet effects);

// Why a scene with `effects` cannot run in this build, and the line to add
// ("" if it can).
std::string kernels_missing(EffectSet effects);

}  // namespace dem2d
