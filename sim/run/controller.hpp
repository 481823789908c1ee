// The run loop's controllers: everything that acts on a run at given steps
// (body removals, the jam remedy, output, stop criteria, the duration). Each
// says when it next needs the loop to stop (`next_step`), acts there, and
// saves and restores its own state in a checkpoint, so the loop in run.cpp
// is written once for all of them:
//
//   each step the loop stops at: every controller whose next_step() is the
//     current step acts, in the order of the list (a fixed order, so that
//     results are reproducible); one that returns a reason ends the run;
//   then it advances to the nearest next_step() of any controller.
//
// What happens between such steps (forces, motion schedules, list rebuilds)
// belongs to the System; what depends on wall time (checkpoint timer,
// progress, signals) belongs to the loop and never changes results.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/step_count.hpp"
#include "engine/system.hpp"

namespace dem2d {

namespace h5 {
class File;
}

// A controller's group in a checkpoint file (written and read by checkpoint.cpp).
class ControllerState {
 public:
  ControllerState(const h5::File& file, std::string group) : file_(file), group_(std::move(group)) {}
  void put(const std::string& key, std::int64_t value) const;
  void put(const std::string& key, double value) const;
  void put(const std::string& key, const std::vector<double>& values) const;
  std::int64_t get_int(const std::string& key) const;
  double get_double(const std::string& key) const;
  std::vector<double> get_doubles(const std::string& key) const;

 private:
  const h5::File& file_;
  std::string group_;
};

// Number of steps in an interval given in seconds (0: off, for intervals <= 0).
inline std::int64_t steps_of_interval(double seconds, double dt) {
  return seconds > 0.0 ? steps_every(seconds, dt) : 0;
}

// A controller's forecast of the run's end, for the progress lines.
struct EndForecast {
  double time = std::numeric_limits<double>::infinity();  // simulated time it ends the run at (s); inf: cannot say
  std::string what;             // what ends it then ("the duration", "intruder clear of the bed + 2 s")
  bool may_end_sooner = false;  // it may end the run at a time it cannot predict (an energy criterion)
};

class Controller {
 public:
  static constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();

  virtual ~Controller() = default;
  // Its group in a checkpoint (unique among a run's controllers).
  virtual std::string name() const = 0;
  // The next step at which it must act (kNever: none).
  virtual std::int64_t next_step() const = 0;
  // Runs when sys.state.step == next_step(). A non-empty result ends the run and
  // is its stop reason.
  virtual std::string act(System& sys) = 0;
  // After act() ended the run: which criterion did (the run file's
  // `stopped_by`: "duration", "body_free", "kinetic_energy", "max_taps").
  virtual std::string stop_criterion() const { return name(); }
  // Its state at the current step, after it acted (may flush buffers first).
  virtual void save(const ControllerState& out) = 0;
  // Replaces the state a fresh start set up with the saved one.
  virtual void restore(const ControllerState& in) = 0;
  // The run ended (any reason but an interruption): last records.
  virtual void finish(System&) {}
  // When it expects to end the run, for the progress lines only (never
  // changes results): see EndForecast.
  virtual EndForecast forecast(const System&) const { return {}; }
};

}  // namespace dem2d
