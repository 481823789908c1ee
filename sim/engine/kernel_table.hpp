// The kernel table: kernels::advance<E> and kernels::initial_forces<E> for
// every valid effect set (is_valid: 288 of the 2^9), split by the two highest
// effect bits into four parts, each instantiated in its own translation unit
// (kernels_part*.cpp) to build in parallel.
#pragma once

#include <array>
#include <utility>

#include "engine/system.hpp"

namespace dem2d {

struct KernelPair {
  AdvanceFn advance;
  ForceFn initial_forces;
};

inline constexpr unsigned kKernelPartBits = effect::count - 2;

template <unsigned Part>
KernelPair kernel_part(EffectSet low_bits);

extern template KernelPair kernel_part<0>(EffectSet);
extern template KernelPair kernel_part<1>(EffectSet);
extern template KernelPair kernel_part<2>(EffectSet);
extern template KernelPair kernel_part<3>(EffectSet);

}  // namespace dem2d
