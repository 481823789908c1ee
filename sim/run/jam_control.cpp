#include "run/jam_control.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/step_count.hpp"

namespace dem2d {

JamController::JamController(const JamControl& spec, const System& sys) : spec_(spec) {
  if (!spec_.enabled) return;
  for (const std::string& name : spec_.bodies) walls_.push_back(sys.body_index(name));
  every_ = steps_every(spec_.check_interval, sys.config.dt);
  no_flow_ = steps_every(spec_.no_flow_time, sys.config.dt);
  half_tap_ = steps_every(0.5 * spec_.tap_duration, sys.config.dt);
  start_ = steps_in(spec_.start_time, sys.config.dt);
  st_.next_check = (start_ + every_ - 1) / every_ * every_;
  st_.last_flow = start_;
}

std::int64_t JamController::next_step() const {
  if (!spec_.enabled) return kNever;
  std::int64_t next = st_.next_check;
  if (st_.tap_reverse >= 0) next = std::min(next, st_.tap_reverse);
  if (st_.tap_end >= 0) next = std::min(next, st_.tap_end);
  return next;
}

void JamController::move_walls(System& sys, double vx, double vy) const {
  for (const std::size_t b : walls_) sys.set_body_velocity(b, vx, vy);
}

std::string JamController::act(System& sys) {
  const std::int64_t step = sys.state.step;
  if (step == st_.tap_reverse) {
    move_walls(sys, -spec_.tap_vx, -spec_.tap_vy);
    st_.tap_reverse = -1;
  }
  if (step == st_.tap_end) {
    move_walls(sys, 0.0, 0.0);
    st_.tap_end = -1;
    st_.last_flow = step;  // give the flow no_flow_time to restart
  }
  if (step != st_.next_check) return "";
  st_.next_check += every_;

  std::int64_t above = 0;
  for (std::size_t i = 0; i < sys.size(); ++i)
    above += sys.state.p.active[i] && sys.state.p.y[i] > spec_.outlet_height;
  if (st_.last_count < 0 || above < st_.last_count) st_.last_flow = step;
  st_.last_count = above;
  const bool tapping = st_.tap_end >= 0;
  if (above == 0 || tapping || step - st_.last_flow < no_flow_) return "";

  // a jam
  st_.jam_times.push_back(sys.time());
  if (static_cast<int>(st_.jam_times.size()) > spec_.max_taps)
    return "hopper outlet jammed: " + std::to_string(spec_.max_taps) + " taps did not clear it";
  move_walls(sys, spec_.tap_vx, spec_.tap_vy);
  st_.tap_reverse = step + half_tap_;
  st_.tap_end = step + 2 * half_tap_;
  return "";
}

// The counters, by their names in a checkpoint.
template <class S>
static auto counters(S& st) {
  return std::array{std::pair{"next_check", &st.next_check}, std::pair{"last_flow", &st.last_flow},
                    std::pair{"last_count", &st.last_count}, std::pair{"tap_reverse", &st.tap_reverse},
                    std::pair{"tap_end", &st.tap_end}};
}

void JamController::save(const ControllerState& out) {
  for (const auto& [key, v] : counters(st_)) out.put(key, *v);
  out.put("jam_times", st_.jam_times);
}

void JamController::restore(const ControllerState& in) {
  for (const auto& [key, v] : counters(st_)) *v = in.get_int(key);
  st_.jam_times = in.get_doubles("jam_times");
}

}  // namespace dem2d
