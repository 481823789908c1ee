// What the scene's keys outside the contact law mean: what each is, its unit
// and its range. The scene reader validates with them (scene/scene_toml.cpp)
// and the run file's /parameters describes its values with them
// (runfile/run_parameters.cpp), so the two cannot drift apart. The law's keys are
// its terms' (contact/contact_law.hpp: contact_law_keys), the motion kinds'
// core/motion.hpp, the shapes' shape/shape_kinds.hpp.
#pragma once

#include "core/key_spec.hpp"

namespace dem2d::scene_key {

inline constexpr Num gravity{"gravity vector", "m/s^2", Rule::finite};
inline constexpr Num density{"grain density", "kg/m^3", Rule::positive};
inline constexpr Num duration{"simulated time", "s", Rule::positive};
inline constexpr Num dt{"time step", "s", Rule::positive};
inline constexpr Num kinetic_energy_below{"total kinetic energy threshold", "J/m", Rule::positive};
inline constexpr Num kinetic_energy_per_grain_below{"kinetic energy threshold per active grain", "J/m", Rule::positive};
inline constexpr Num all_below{"height every grain must be below", "m", Rule::finite};
inline constexpr Num free_time{"time without contact", "s", Rule::positive};
inline constexpr Num check_interval{"interval between checks", "s", Rule::positive};
inline constexpr Num min_time{"time before the first check", "s", Rule::non_negative};
inline constexpr Num domain_bound{"domain bound", "m", Rule::finite};
inline constexpr Num skin{"Verlet-list skin", "m", Rule::positive};
inline constexpr Num output_interval{"interval, 0 = off", "s", Rule::non_negative};
inline constexpr Num checkpoint_interval{"wall-clock interval, 0 = off", "s", Rule::non_negative};
// A scene that does not give checkpoint_interval: a checkpoint every 5 min of
// wall time (s), so that a killed run resumes (one costs ~5 ms for the
// 1600-grain bed: docs/engine.md, "Checkpoint/restart").
inline constexpr double kDefaultCheckpointInterval = 300.0;
inline constexpr Num displacement_window{"window of the displacement stored with each snapshot, 0 = off", "s",
                                         Rule::non_negative};
inline constexpr Num thickness{"rounding diameter (a segment's cap diameter d_s)", "m", Rule::non_negative};
inline constexpr Num body_velocity{"prescribed velocity", "m/s", Rule::finite};
inline constexpr Num remove_at{"time the body is taken away", "s", Rule::non_negative};
inline constexpr Num vertex{"core vertex at the start", "m", Rule::finite};
inline constexpr Num segment_duration{"segment duration", "s", Rule::positive};
inline constexpr Num segment_velocity{"velocity (a ramp's at its end)", "m/s", Rule::finite};
inline constexpr Num amplitude{"peak displacement of a cycle", "m", Rule::finite};
inline constexpr Num angular_velocity{"angular velocity about the pivot (a ramp's at its end), counter-clockwise", "rad/s",
                                      Rule::finite};
inline constexpr Num angle{"peak angle of a cycle about the pivot, counter-clockwise", "rad", Rule::finite};
inline constexpr Num pivot{"point the body turns about, at the start", "m", Rule::finite};
inline constexpr Num period{"period of a cycle", "s", Rule::positive};
inline constexpr Num outlet_height{"height of the hopper outlet", "m", Rule::finite};
inline constexpr Num jam_start_time{"time the outlet opens", "s", Rule::non_negative};
inline constexpr Num no_flow_time{"time without outflow that makes a jam", "s", Rule::positive};
inline constexpr Num tap_velocity{"tap velocity, first half of a tap", "m/s", Rule::finite};
inline constexpr Num tap_duration{"duration of a tap, there and back", "s", Rule::positive};

}  // namespace dem2d::scene_key
