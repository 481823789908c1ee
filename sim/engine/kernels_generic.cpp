#include "engine/kernel_table.hpp"
#include "engine/kernels.hpp"

namespace dem2d {

const KernelEntry& generic_kernel() {
  static constexpr KernelEntry kGeneric{effect::generic, &kernels::advance<effect::generic>,
                                        &kernels::initial_forces<effect::generic>};
  return kGeneric;
}

}  // namespace dem2d
