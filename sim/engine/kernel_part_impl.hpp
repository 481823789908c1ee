// Definition of kernel_part<Part>, included only by the kernels_part*.cpp files.
#pragma once

#include "engine/kernel_table.hpp"
#include "engine/kernels.hpp"

namespace dem2d {

// The kernels of effect set E, or none for a set the engine does not run
// (is_valid): those are never instantiated.
template <EffectSet E>
constexpr KernelPair kernels_of() {
  if constexpr (is_valid(E))
    return {&kernels::advance<E>, &kernels::initial_forces<E>};
  else
    return {nullptr, nullptr};
}

template <EffectSet Base, std::size_t... I>
constexpr std::array<KernelPair, sizeof...(I)> make_kernel_part(std::index_sequence<I...>) {
  return {kernels_of<Base + I>()...};
}

template <unsigned Part>
KernelPair kernel_part(EffectSet low_bits) {
  static constexpr auto table =
      make_kernel_part<Part << kKernelPartBits>(std::make_index_sequence<1u << kKernelPartBits>{});
  return table[low_bits];
}

}  // namespace dem2d
