#include "run/output_control.hpp"

#include <algorithm>

namespace dem2d {

OutputController::OutputController(const Scene& scene, RunRecorder& recorder)
    : recorder_(recorder),
      every_series_(steps_of_interval(scene.output.series_interval, scene.dt)),
      every_snapshot_(steps_of_interval(scene.output.snapshot_interval, scene.dt)),
      window_(every_snapshot_ ? steps_of_interval(scene.output.displacement_window, scene.dt) : 0) {
  if (!every_series_) next_series_ = kNever;
  if (!every_snapshot_) next_snapshot_ = kNever;
}

std::int64_t OutputController::next_step() const {
  std::int64_t next = std::min(next_series_, next_snapshot_);
  // the reference for the next snapshot, unless taken or already past
  if (window_ && ref_for_ != next_snapshot_ && ref_step() > last_snapshot_)
    next = std::min(next, ref_step());
  return next;
}

void OutputController::take_reference(const System& sys) {
  ref_for_ = next_snapshot_;
  ref_position_.resize(2 * sys.size());
  for (std::size_t i = 0; i < sys.size(); ++i) {
    ref_position_[2 * i] = sys.state.p.x[i];
    ref_position_[2 * i + 1] = sys.state.p.y[i];
  }
}

std::string OutputController::act(System& sys) {
  if (sys.state.step == next_series_) {
    recorder_.record_series(sys);
    last_series_ = sys.state.step;
    next_series_ += every_series_;
  }
  if (window_ && sys.state.step == ref_step()) take_reference(sys);
  if (sys.state.step == next_snapshot_) {
    recorder_.record_snapshot(sys, ref_for_ == sys.state.step ? &ref_position_ : nullptr);
    ref_for_ = -1;
    last_snapshot_ = sys.state.step;
    next_snapshot_ += every_snapshot_;
    // a window as long as the interval starts at this snapshot
    if (window_ && sys.state.step == ref_step()) take_reference(sys);
  }
  return "";
}

void OutputController::finish(System& sys) {
  // the final state always ends the run file, so that later stages can start from it
  if (every_series_ && last_series_ != sys.state.step) recorder_.record_series(sys);
  if (last_snapshot_ != sys.state.step) recorder_.record_snapshot(sys);
}

void OutputController::save(const ControllerState& out) {
  recorder_.flush_segment();
  out.put("segments", static_cast<std::int64_t>(recorder_.segments()));
  out.put("series_rows", recorder_.series_rows());
  out.put("snapshots", recorder_.snapshot_count());
  out.put("next_series", next_series_);
  out.put("next_snapshot", next_snapshot_);
  out.put("last_series", last_series_);
  out.put("last_snapshot", last_snapshot_);
  out.put("ref_for", ref_for_);
  out.put("ref_position", ref_position_);
}

void OutputController::restore(const ControllerState& in) {
  recorder_.restore_counts(static_cast<int>(in.get_int("segments")), in.get_int("series_rows"),
                           in.get_int("snapshots"));
  next_series_ = in.get_int("next_series");
  next_snapshot_ = in.get_int("next_snapshot");
  last_series_ = in.get_int("last_series");
  last_snapshot_ = in.get_int("last_snapshot");
  ref_for_ = in.get_int("ref_for");
  ref_position_ = in.get_doubles("ref_position");
}

}  // namespace dem2d
