#include "engine/kernel_part_impl.hpp"

namespace dem2d {
template KernelPair kernel_part<1>(EffectSet);
}  // namespace dem2d
