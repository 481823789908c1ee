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

const KernelEntry& lookup(EffectSet effects) {
  if (const KernelEntry* k = find(effects)) return *k;
  throw std::invalid_argument(kernels_missing(effects));
}

}  // namespace

bool kernels_compiled(EffectSet effects) { return find(effects) != nullptr; }

std::string kernels_missing(EffectSet effects) {
  if (kernels_compiled(effects)) return "";
  if (!is_valid(effects))
    return "effect set {" + effect_names(effects) +
           "} is not valid (unknown bits, or an effect without the one it needs)";
  return "this build has no kernels for the effect set {" + effect_names(effects) +
         "}: add the line\n  \"" + effect_names(effects) +
         "\",\nto sim/engine/kernel_sets.inc and rebuild (docs/engine.md, \"Effect sets\")";
}

AdvanceFn advance_kernel(EffectSet effects) { return lookup(effects).advance; }
ForceFn initial_force_kernel(EffectSet effects) { return lookup(effects).initial_forces; }

}  // namespace dem2d
