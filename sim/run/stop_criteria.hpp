// The scene's stop criteria ([stop]): the duration, and the earlier ends
// tested every check_interval from min_time on (kinetic energy with every
// grain below a height; a body free of the bed for free_time).
#pragma once

#include <cstdint>

#include "core/step_count.hpp"
#include "run/controller.hpp"

namespace dem2d {

// Ends the run when stop.duration is reached.
class DurationLimit final : public Controller {
 public:
  explicit DurationLimit(const Scene& scene)
      : last_(steps_in(scene.stop.duration, scene.dt)), end_(static_cast<double>(last_) * scene.dt) {}
  std::string name() const override { return "duration"; }
  std::int64_t next_step() const override { return last_; }
  std::string act(System&) override { return "duration reached"; }
  void save(const ControllerState&) override {}
  void restore(const ControllerState&) override {}
  EndForecast forecast(const System&) const override { return {end_, "the duration", false}; }
  std::int64_t last_step() const { return last_; }

 private:
  std::int64_t last_;
  double end_;  // (s)
};

// The earlier ends (kNever if the scene sets none).
class StopCriteria final : public Controller {
 public:
  StopCriteria(const Scene& scene, const System& sys);
  std::string name() const override { return "stop"; }
  std::int64_t next_step() const override { return next_check_; }
  std::string act(System& sys) override;
  std::string stop_criterion() const override { return met_; }
  void save(const ControllerState& out) override;
  void restore(const ControllerState& in) override;
  // body_free: when the body's bottom, rising at its current velocity, clears
  // the bed beside it, plus free_time; the energy criterion cannot be foreseen.
  EndForecast forecast(const System& sys) const override;

 private:
  std::string met_;  // the criterion act() found met: "body_free" or "kinetic_energy"
  StopCondition stop_;
  bool energy_ = false, free_ = false;
  std::size_t free_body_ = 0;
  std::int64_t every_ = 0, free_steps_ = 0;
  std::int64_t next_check_ = kNever;
  std::int64_t last_contact_ = 0;  // last step the stop.body_free body was held by the bed
};

}  // namespace dem2d
