// Definition of kernel_part<Part>, included only by the kernels_part*.cpp files.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>
#include <utility>

#include "engine/kernel_sets.hpp"
#include "engine/kernel_table.hpp"
#include "engine/kernels.hpp"

namespace dem2d {

namespace kernel_sets {

#ifdef DEM2D_ALL_KERNEL_SETS
// every valid set, in the order of their bits
constexpr std::size_t kCount = [] {
  std::size_t n = 0;
  for (EffectSet e = 0; e <= effect::all; ++e) n += is_valid(e);
  return n;
}();
constexpr EffectSet set(std::size_t k) {
  for (EffectSet e = 0; e <= effect::all; ++e)
    if (is_valid(e) && k-- == 0) return e;
  return 0;
}
#else
#ifndef DEM2D_KERNEL_SETS_FILE
#define DEM2D_KERNEL_SETS_FILE "engine/kernel_sets.inc"
#endif
inline constexpr std::string_view kNames[] = {
#include DEM2D_KERNEL_SETS_FILE
};
constexpr std::size_t kCount = std::size(kNames);
constexpr EffectSet set(std::size_t k) { return parse_effect_set(kNames[k]).value_or(0); }

// The list must name known effects, sets the engine runs, each once.
constexpr bool listed_well() {
  for (std::size_t k = 0; k < kCount; ++k) {
    const auto e = parse_effect_set(kNames[k]);
    if (!e || !is_valid(*e)) return false;
    for (std::size_t j = 0; j < k; ++j)
      if (set(j) == *e) return false;
  }
  return true;
}
static_assert(listed_well(), "the kernel set list names an unknown effect, an effect without the one it needs "
                             "(core/effects.hpp: kEffectNeeds), or a set twice");
#endif

template <std::size_t K>
constexpr KernelEntry entry() {
  constexpr EffectSet E = set(K);
  return {E, &kernels::advance<E>, &kernels::initial_forces<E>};
}

template <unsigned Part, std::size_t... I>
constexpr auto part(std::index_sequence<I...>) {
  return std::array<KernelEntry, sizeof...(I)>{entry<Part + kKernelParts * I>()...};
}

}  // namespace kernel_sets

template <unsigned Part>
std::span<const KernelEntry> kernel_part() {
  constexpr std::size_t n = kernel_sets::kCount > Part ? (kernel_sets::kCount - Part + kKernelParts - 1) / kKernelParts : 0;
  static constexpr auto table = kernel_sets::part<Part>(std::make_index_sequence<n>{});
  return table;
}

}  // namespace dem2d
