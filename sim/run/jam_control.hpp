// Clears clogs of a hopper outlet (scene table [jam], JamControl in scene.hpp).
//
// Every check_interval it counts the active grains above the outlet. A jam
// is no decrease of that count for no_flow_time while grains remain (and
// after start_time, when the outlet opens). The remedy is physical: the
// hopper walls are tapped, moved at tap_velocity for half of tap_duration and
// back at -tap_velocity for the other half, which loosens the arch over the
// outlet. After a tap the controller waits no_flow_time again before the next.
// Everything it decides depends only on the state at fixed steps, so runs
// with taps stay bitwise reproducible and restartable.
#pragma once

#include <cstdint>
#include <vector>

#include "run/controller.hpp"
#include "scene/scene.hpp"

namespace dem2d {

class JamController final : public Controller {
 public:
  JamController(const JamControl& spec, const System& sys);

  std::string name() const override { return "jam"; }
  std::string stop_criterion() const override { return "max_taps"; }
  // A check or a tap turning (kNever without [jam]).
  std::int64_t next_step() const override;
  // Ends the run once a jam was detected after max_taps taps (the hopper
  // cannot be emptied).
  std::string act(System& sys) override;
  void save(const ControllerState& out) override;
  void restore(const ControllerState& in) override;

  const std::vector<double>& jam_times() const { return st_.jam_times; }

 private:
  // What a checkpoint keeps (save, restore).
  struct State {
    std::int64_t next_check = 0;     // step of the next count
    std::int64_t last_flow = 0;      // last step at which grains left the hopper
    std::int64_t last_count = -1;    // grains above the outlet at the last check
    std::int64_t tap_reverse = -1;   // steps at which the tap in progress turns back / ends (-1: none)
    std::int64_t tap_end = -1;
    std::vector<double> jam_times;   // (s)
  };
  void move_walls(System& sys, double vx, double vy) const;

  JamControl spec_;
  std::vector<std::size_t> walls_;
  std::int64_t every_ = 1, no_flow_ = 1, half_tap_ = 1, start_ = 0;
  State st_;
};

}  // namespace dem2d
