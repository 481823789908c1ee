// Output on the scene's schedule ([output]): a time-series row every
// series_interval, a snapshot every snapshot_interval with, when
// displacement_window > 0, the displacement over the window before it
// (positions taken window steps earlier), and the final state at the end.
#pragma once

#include <cstdint>
#include <vector>

#include "run/controller.hpp"
#include "writer/run_file.hpp"

namespace dem2d {

class OutputController final : public Controller {
 public:
  OutputController(const Scene& scene, RunRecorder& recorder);

  std::string name() const override { return "output"; }
  std::int64_t next_step() const override;
  std::string act(System& sys) override;
  void save(const ControllerState& out) override;  // flushes the recorder first
  void restore(const ControllerState& in) override;
  // Records the final state unless this step was already recorded.
  void finish(System& sys) override;

  double displacement_window(double dt) const { return static_cast<double>(window_) * dt; }

 private:
  std::int64_t ref_step() const { return next_snapshot_ - window_; }
  void take_reference(const System& sys);

  RunRecorder& recorder_;
  std::int64_t every_series_ = 0, every_snapshot_ = 0, window_ = 0;  // steps (0: off)
  std::int64_t next_series_ = 0, next_snapshot_ = 0;
  std::int64_t last_series_ = -1, last_snapshot_ = -1;
  // positions taken for the displacement of the snapshot at step ref_for_ (-1: none)
  std::int64_t ref_for_ = -1;
  std::vector<double> ref_position_;  // x0, y0, x1, y1, ... (m)
};

}  // namespace dem2d
