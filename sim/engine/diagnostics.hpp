// Whole-system quantities, computed serially in index order so that they are
// identical whatever the thread count (the stop criterion depends on them).
#pragma once

#include <cstddef>

#include "engine/system.hpp"

namespace dem2d {

// Translational + rotational kinetic energy of the active grains (J/m).
double kinetic_energy(const System& sys);

// Whether the kinetic-energy stop criterion of `stop` holds: the total below
// stop.kinetic_energy_below, or the mean per active grain below
// stop.kinetic_energy_per_grain_below (whichever is set).
bool kinetic_energy_criterion_met(const System& sys, const StopCondition& stop);

// Elastic energy stored in the contacts (J/m): normal springs, and the
// tangential and rolling springs when those effects are on; by kind, and total.
Stored spring_energy(const System& sys);
double elastic_energy(const System& sys);

// Gravitational potential energy -m g.r of the active grains (J/m).
double gravity_energy(const System& sys);

// Height of the highest active grain centre (m); -inf without grains.
double highest_grain(const System& sys);

// Top of the bed beside body b (m): the highest top (y + radius) of the
// active grains whose centre lies outside the body's horizontal extent
// widened by its rounding and the largest grain diameter (grains it carries
// are not the bed); -inf without such grains.
double bed_surface_beside(const System& sys, std::size_t b);

// Whether body b is still held by the bed: some grain touching it is
// connected, through touching grains, to a grain touching another body
// (walls, floor). Grains carried on it (a cluster touching nothing else) do
// not count.
bool held_by_bed(const System& sys, std::size_t b);

// Largest overlap over all touching contacts (m), and their number.
double max_overlap(const System& sys);
std::size_t contact_count(const System& sys);
// The touching grain-grain contacts among them.
std::size_t pair_contact_count(const System& sys);

}  // namespace dem2d
