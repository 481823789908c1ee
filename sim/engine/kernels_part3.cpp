#include "engine/kernel_part_impl.hpp"

namespace dem2d {
template std::span<const KernelEntry> kernel_part<3>();
}  // namespace dem2d
