// The kernel table: kernels::advance<E> and kernels::initial_forces<E> for
// every effect set this build specialises (engine/kernel_sets.hpp), split
// into four parts, each instantiated in its own translation unit
// (kernels_part*.cpp) to build in parallel; and the generic kernel
// (kernels_generic.cpp), which runs every other valid set.
#pragma once

#include <span>

#include "engine/system.hpp"

namespace dem2d {

struct KernelEntry {
  EffectSet effects;
  AdvanceFn advance;
  ForceFn initial_forces;
};

inline constexpr unsigned kKernelParts = 4;

// Part `Part` of the table: the sets k with k % kKernelParts == Part.
template <unsigned Part>
std::span<const KernelEntry> kernel_part();

extern template std::span<const KernelEntry> kernel_part<0>();
extern template std::span<const KernelEntry> kernel_part<1>();
extern template std::span<const KernelEntry> kernel_part<2>();
extern template std::span<const KernelEntry> kernel_part<3>();

// The generic kernel: every term compiled in, the scene's set tested at run
// time (E = effect::generic, core/effects.hpp).
const KernelEntry& generic_kernel();

}  // namespace dem2d
