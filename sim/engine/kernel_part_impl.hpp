// Definition of kernel_part<Part>, included only by the kernels_part*.cpp files.
#pragma once

#include "engine/kernel_table.hpp"
#include "engine/kernels.hpp"

namespace dem2d {

template <EffectSet Base, std::size_t... I>
constexpr std::array<KernelPair, sizeof...(I)> make_kernel_part(std::index_sequence<I...>) {
  return {KernelPair{&kernels::advance<Base + I>, &kernels::initial_forces<Base + I>}...};
}

template <unsigned Part>
KernelPair kernel_part(EffectSet low_bits) {
  static constexpr auto table =
      make_kernel_part<Part << kKernelPartBits>(std::make_index_sequence<1u << kKernelPartBits>{});
  return table[low_bits];
}

}  // namespace dem2d
