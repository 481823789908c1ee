// The physics of a progress line (what LAMMPS calls thermo output): the
// kinetic energy, the contacts per grain, the largest overlap over the mean
// diameter, the grains lost, and the force on each body that moves. Read from
// the state between steps, serially: never changes results.
#pragma once

#include <string>

#include "engine/system.hpp"

namespace dem2d {

// "KE 3.2e-05 J/m  contacts/grain 3.41  max overlap/d 0.0021  lost 0  F(intruder) (0.1, 57.3) N/m"
std::string thermo_text(const System& sys);

}  // namespace dem2d
