#include "run/run.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "engine/diagnostics.hpp"
#include "engine/system.hpp"
#include "io/run_file.hpp"
#include "run/checkpoint.hpp"

namespace dem2d {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

std::atomic<bool> g_interrupt{false};
static_assert(std::atomic<bool>::is_always_lock_free);

// Number of steps in an interval given in seconds (0 = off).
std::int64_t steps_of(double interval, double dt) {
  if (interval <= 0.0) return 0;
  return std::max<std::int64_t>(1, std::llround(interval / dt));
}

std::string format_duration(double seconds) {
  const auto s = static_cast<long long>(seconds);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%lld:%02lld:%02lld", s / 3600, s / 60 % 60, s % 60);
  return buf;
}

class Progress {
 public:
  Progress(bool on, std::int64_t total_steps, std::size_t particles, std::int64_t step)
      : on_(on), total_(total_steps), particles_(particles), last_step_(step) {}
  // The rate shown is averaged over the time since the previous line.
  void update(std::int64_t step, double t) {
    if (!on_) return;
    const auto now = Clock::now();
    const double secs = std::chrono::duration<double>(now - last_).count();
    if (secs < 0.5) return;
    const double steps_per_s = static_cast<double>(step - last_step_) / secs;
    last_ = now;
    last_step_ = step;
    const double eta = steps_per_s > 0 ? static_cast<double>(total_ - step) / steps_per_s : 0.0;
    std::fprintf(stderr, "\r[dem2d] t = %.6g s  step %lld/%lld  %.3g steps/s  %.3g particle-steps/s  ETA %s   ",
                 t, static_cast<long long>(step), static_cast<long long>(total_), steps_per_s,
                 steps_per_s * static_cast<double>(particles_), format_duration(eta).c_str());
    std::fflush(stderr);
  }
  void done() {
    if (on_) std::fprintf(stderr, "\n");
  }

 private:
  bool on_;
  std::int64_t total_;
  std::size_t particles_;
  std::int64_t last_step_;
  Clock::time_point last_ = Clock::now();
};

}  // namespace

void request_interrupt() { g_interrupt.store(true); }

RunReport run_scene(const Scene& scene, const RunOptions& opt) {
  g_interrupt.store(false);
  const auto t_start = Clock::now();
  const fs::path out_dir(opt.out_dir);
  const fs::path work = out_dir / ".run.work";
  const std::string ckpt = (work / "checkpoint.h5").string();
  fs::create_directories(out_dir);

  System sys(scene);
  RunReport report;
  RunProgress pr;
  const std::int64_t every_series = steps_of(scene.output.series_interval, scene.dt);
  const std::int64_t every_snapshot = steps_of(scene.output.snapshot_interval, scene.dt);
  const bool energy_stop = scene.stop.kinetic_energy_below > 0.0;
  const std::int64_t every_check = energy_stop ? steps_of(scene.stop.check_interval, scene.dt) : 0;
  const std::int64_t total = std::llround(scene.stop.duration / scene.dt);

  if (!opt.fresh && fs::exists(ckpt)) {
    if (checkpoint_scene_text(ckpt) != scene.text)
      throw std::runtime_error(ckpt + " was written by a different scene; rerun with --fresh to discard it");
    pr = read_checkpoint(ckpt, sys);
    report.resumed = true;
  } else {
    fs::remove_all(work);
    fs::create_directories(work);
    if (energy_stop) {  // first test at the first multiple of the interval at or after min_time
      const std::int64_t first = std::llround(std::ceil(scene.stop.min_time / scene.dt));
      pr.next_check = std::max<std::int64_t>(every_check, (first + every_check - 1) / every_check * every_check);
    }
  }
  RunRecorder recorder(sys, work.string());
  if (report.resumed) recorder.restore_counts(pr.segments, pr.series_rows, pr.snapshots);

  auto checkpoint = [&] {
    recorder.flush_segment();
    pr.segments = recorder.segments();
    pr.series_rows = recorder.series_rows();
    pr.snapshots = recorder.snapshot_count();
    write_checkpoint(ckpt, sys, pr, scene.text);
  };

  const std::int64_t first_step = sys.step;
  Progress progress(opt.progress, total, sys.size(), first_step);
  auto finish_report = [&](bool complete) {
    report.complete = complete;
    report.final_step = sys.step;
    report.steps = sys.step - first_step;
    report.wall_seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
    const auto active = static_cast<double>(std::count(sys.p.active.begin(), sys.p.active.end(), 1));
    if (report.steps > 0 && active > 0)
      report.ns_per_particle_step = report.wall_seconds * 1e9 / (static_cast<double>(report.steps) * active);
    report.lost = sys.lost.size();
    return report;
  };
  auto last_checkpoint = Clock::now();
  std::int64_t chunk = 64;
  std::int64_t last_series = -1, last_snapshot = -1;
  while (true) {
    // events due at this step
    if (every_series && sys.step == pr.next_series) {
      recorder.record_series(sys);
      last_series = sys.step;
      pr.next_series += every_series;
    }
    if (every_snapshot && sys.step == pr.next_snapshot) {
      recorder.record_snapshot(sys);
      last_snapshot = sys.step;
      pr.next_snapshot += every_snapshot;
    }
    if (energy_stop && sys.step == pr.next_check) {
      pr.next_check += every_check;
      if (kinetic_energy(sys) < scene.stop.kinetic_energy_below) {
        std::ostringstream why;
        why << "kinetic energy below " << scene.stop.kinetic_energy_below << " J/m";
        report.stop_reason = why.str();
        break;
      }
    }
    if (sys.step >= total) {
      report.stop_reason = "duration reached";
      break;
    }
    if (g_interrupt.load() || sys.step == opt.interrupt_at_step) {
      checkpoint();
      progress.done();
      return finish_report(false);
    }
    if (scene.output.checkpoint_interval > 0.0 &&
        std::chrono::duration<double>(Clock::now() - last_checkpoint).count() >= scene.output.checkpoint_interval) {
      checkpoint();
      last_checkpoint = Clock::now();
    }

    std::int64_t target = std::min(total, sys.step + chunk);
    if (every_series) target = std::min(target, pr.next_series);
    if (every_snapshot) target = std::min(target, pr.next_snapshot);
    if (energy_stop) target = std::min(target, pr.next_check);
    if (opt.interrupt_at_step > sys.step) target = std::min(target, opt.interrupt_at_step);
    const auto t0 = Clock::now();
    const std::int64_t n = target - sys.step;
    sys.advance(n);
    const double secs = std::chrono::duration<double>(Clock::now() - t0).count();
    const double rate = secs > 0 ? static_cast<double>(n) / secs : 0.0;
    // aim at ~0.1 s per call: responsive to signals and checkpoints, negligible overhead
    if (n == chunk) chunk = std::clamp<std::int64_t>(static_cast<std::int64_t>(rate * 0.1), 1, 1 << 24);
    progress.update(sys.step, sys.time());
  }
  progress.done();

  // the final state always ends the run file, so that later stages can start from it
  if (every_series && last_series != sys.step) recorder.record_series(sys);
  if (last_snapshot != sys.step) recorder.record_snapshot(sys);

  const RunInfo info{scene.text, scene.path, std::string(DEM2D_VERSION), sys.threads};
  report.run_file = (out_dir / "run.h5").string();
  recorder.finish(sys, info, report.run_file, report.stop_reason);
  fs::remove_all(work);

  return finish_report(true);
}

}  // namespace dem2d
