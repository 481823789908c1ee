#include "run/stop_criteria.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/number_text.hpp"
#include "core/step_count.hpp"
#include "engine/diagnostics.hpp"

namespace dem2d {

StopCriteria::StopCriteria(const Scene& scene, const System& sys)
    : stop_(scene.stop), energy_(stop_.energy_criterion()), free_(!stop_.body_free.empty()) {
  if (!energy_ && !free_) return;
  every_ = steps_of_interval(stop_.check_interval, scene.dt);
  if (every_ == 0) return;  // never tested
  if (free_) {
    free_body_ = sys.body_index(stop_.body_free);
    free_steps_ = steps_of_interval(stop_.free_time, scene.dt);
  }
  // first test at the first multiple of the interval at or after min_time
  const std::int64_t first = steps_up(stop_.min_time, scene.dt);
  next_check_ = std::max<std::int64_t>(every_, (first + every_ - 1) / every_ * every_);
}

std::string StopCriteria::act(System& sys) {
  next_check_ += every_;
  if (free_ && held_by_bed(sys, free_body_)) last_contact_ = sys.state.step;
  if (free_ && sys.state.step - last_contact_ >= free_steps_) {
    met_ = "body_free";
    return "body " + stop_.body_free + " free of the bed for " + shortest(stop_.free_time) + " s";
  }
  if (energy_ && kinetic_energy_criterion_met(sys, stop_) && highest_grain(sys) < stop_.all_below) {
    met_ = "kinetic_energy";
    std::ostringstream why;
    if (stop_.kinetic_energy_per_grain_below > 0.0)
      why << "kinetic energy below " << stop_.kinetic_energy_per_grain_below << " J/m per grain";
    else
      why << "kinetic energy below " << stop_.kinetic_energy_below << " J/m";
    if (stop_.all_below < 1e300) why << " with every grain below " << stop_.all_below << " m";
    return why.str();
  }
  return "";
}

EndForecast StopCriteria::forecast(const System& sys) const {
  EndForecast f;
  f.may_end_sooner = energy_ && every_ > 0;
  if (!free_ || every_ == 0) return f;
  const Bodies& B = sys.state.bodies;
  const double vy = B.vy[free_body_];
  const double surface = bed_surface_beside(sys, free_body_);
  if (!B.active[free_body_] || !(vy > 0.0) || !std::isfinite(surface)) return f;
  const double bottom = core_bounds(B.shape[free_body_]).ymin - B.radius[free_body_];
  const double now = sys.time(), last_held = static_cast<double>(last_contact_) * sys.config.dt;
  const double clear = bottom < surface ? now + (surface - bottom) / vy : std::max(now, last_held);
  f.time = std::max(clear + stop_.free_time, now);
  f.what = stop_.body_free + " clear of the bed + " + shortest(stop_.free_time) + " s";
  return f;
}

void StopCriteria::save(const ControllerState& out) {
  out.put("next_check", next_check_);
  out.put("last_contact", last_contact_);
}

void StopCriteria::restore(const ControllerState& in) {
  next_check_ = in.get_int("next_check");
  last_contact_ = in.get_int("last_contact");
}

}  // namespace dem2d
