#include "engine/kernel_table.hpp"

#include <stdexcept>
#include <string>

#include "engine/kernel_sets.hpp"

namespace dem2d {

namespace {

const KernelEntry* find(EffectSet effects) {
  for (const auto part : {kernel_part<0>(), kernel_part<1>(), kernel_part<2>(), kernel_part<3>()})
    for (const KernelEntry& k : part)
      if (k.effects == effects) return &k;
  return nullptr;
}

const KernelEntry& lookup(EffectSet effects, bool generic) {
  if (const KernelEntry* k = find(effects); k && !generic) return *k;
  if (is_valid(effects)) return generic_kernel();
  throw std::invalid_argument("effect set {" + effect_names(effects) +
                              "} is not valid (unknown bits, or an effect without the one it needs)");
}

}  // namespace

bool kernels_specialised(EffectSet effects) { return find(effects) != nullptr; }

std::string kernel_description(EffectSet effects, bool generic) {
  if (kernels_specialised(effects) && !generic) return "kernel specialised for {" + effect_names(effects) + "}";
  return "generic kernel for {" + effect_names(effects) +
         "} (the effects tested at run time: slower than a specialised kernel, docs/performance.md)";
}

AdvanceFn advance_kernel(EffectSet effects, bool generic) { return lookup(effects, generic).advance; }
ForceFn initial_force_kernel(EffectSet effects, bool generic) { return lookup(effects, generic).initial_forces; }

}  // namespace dem2d
