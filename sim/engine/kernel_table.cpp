#include "engine/kernel_table.hpp"

#include <stdexcept>
#include <string>

namespace dem2d {

namespace {
KernelPair lookup(EffectSet effects) {
  if (!is_valid(effects))
    throw std::invalid_argument("effect set " + effect_names(effects) +
                                " is not valid (unknown bits, or an effect without the one it needs)");
  const EffectSet low = effects & ((1u << kKernelPartBits) - 1);
  switch (effects >> kKernelPartBits) {
    case 0: return kernel_part<0>(low);
    case 1: return kernel_part<1>(low);
    case 2: return kernel_part<2>(low);
    default: return kernel_part<3>(low);
  }
}
}  // namespace

AdvanceFn advance_kernel(EffectSet effects) { return lookup(effects).advance; }
ForceFn initial_force_kernel(EffectSet effects) { return lookup(effects).initial_forces; }

}  // namespace dem2d
