#include "run/run.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "core/version.hpp"
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

// How far a run is: a live line on a terminal (every 0.5 s) and a line in
// DIR/run.log (every kLogSeconds of wall time), each with the simulated time,
// the step against the duration's, the rate since its previous line and the
// time left at that rate (an upper bound: a stop criterion may end the run
// sooner). The log also says when the run starts, resumes, checkpoints and ends.
class Progress {
 public:
  static constexpr double kLogSeconds = 60.0;

  Progress(bool terminal, const fs::path& log, std::int64_t total_steps, std::size_t particles, std::int64_t step)
      : terminal_(terminal), log_(std::fopen(log.string().c_str(), "a")), total_(total_steps), particles_(particles),
        term_{Clock::now(), step}, file_{Clock::now(), step} {}
  ~Progress() {
    if (log_) std::fclose(log_);
  }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void update(std::int64_t step, double t) {
    const auto now = Clock::now();
    if (terminal_ && seconds(term_, now) >= 0.5) {
      std::fprintf(stderr, "\r[dem2d] %s   ", line(term_, now, step, t).c_str());
      std::fflush(stderr);
    }
    if (log_ && seconds(file_, now) >= kLogSeconds) note(line(file_, now, step, t));
  }
  // A line in the log, stamped with the date and time.
  void note(const std::string& what) {
    if (!log_) return;
    const std::time_t now = std::time(nullptr);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y-%m-%d %H:%M:%S", std::localtime(&now));
    std::fprintf(log_, "%s %s\n", stamp, what.c_str());
    std::fflush(log_);
  }
  void done() {
    if (terminal_) std::fprintf(stderr, "\n");
  }

 private:
  struct Mark {
    Clock::time_point when;
    std::int64_t step;
  };
  static double seconds(const Mark& m, Clock::time_point now) { return std::chrono::duration<double>(now - m.when).count(); }
  // The rate is averaged since the mark, which moves to now.
  std::string line(Mark& m, Clock::time_point now, std::int64_t step, double t) const {
    const double steps_per_s = static_cast<double>(step - m.step) / std::max(seconds(m, now), 1e-9);
    m = {now, step};
    const double eta = steps_per_s > 0 ? static_cast<double>(total_ - step) / steps_per_s : 0.0;
    char buf[200];
    std::snprintf(buf, sizeof buf, "t = %.6g s  step %lld/%lld (%.1f %%)  %.3g steps/s  %.3g particle-steps/s  ETA %s", t,
                  static_cast<long long>(step), static_cast<long long>(total_),
                  total_ > 0 ? 100.0 * static_cast<double>(step) / static_cast<double>(total_) : 100.0, steps_per_s,
                  steps_per_s * static_cast<double>(particles_), format_duration(eta).c_str());
    return buf;
  }

  bool terminal_;
  std::FILE* log_;
  std::int64_t total_;
  std::size_t particles_;
  Mark term_, file_;
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
  JamController jam(scene.jam, sys);
  RunReport report;
  RunProgress pr;
  const std::int64_t every_series = steps_of(scene.output.series_interval, scene.dt);
  const std::int64_t every_snapshot = steps_of(scene.output.snapshot_interval, scene.dt);
  // PIV-like displacements: positions are taken `window` steps before each scheduled snapshot
  const std::int64_t window = every_snapshot ? steps_of(scene.output.displacement_window, scene.dt) : 0;
  const StopCondition& stop = scene.stop;
  const bool energy_stop = stop.energy_criterion();
  const bool free_stop = !stop.body_free.empty();
  const std::int64_t every_check = energy_stop || free_stop ? steps_of(stop.check_interval, scene.dt) : 0;
  const std::size_t free_body = free_stop ? sys.body_index(stop.body_free) : 0;
  const std::int64_t free_steps = free_stop ? steps_of(stop.free_time, scene.dt) : 0;
  const std::int64_t total = std::llround(stop.duration / scene.dt);
  // bodies taken away during the run, by step
  std::vector<std::pair<std::int64_t, std::size_t>> removals;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    if (scene.bodies[b].remove_at >= 0.0) removals.emplace_back(std::llround(scene.bodies[b].remove_at / scene.dt), b);
  std::sort(removals.begin(), removals.end());

  if (!opt.fresh && fs::exists(ckpt)) {
    if (checkpoint_scene_text(ckpt) != scene.text)
      throw std::runtime_error(ckpt + " was written by a different scene; rerun with --fresh to discard it");
    pr = read_checkpoint(ckpt, sys);
    jam.restore(pr.jam);
    report.resumed = true;
  } else {
    fs::remove_all(work);
    fs::create_directories(work);
    if (every_check) {  // first test at the first multiple of the interval at or after min_time
      const std::int64_t first = std::llround(std::ceil(stop.min_time / scene.dt));
      pr.next_check = std::max<std::int64_t>(every_check, (first + every_check - 1) / every_check * every_check);
    }
  }
  // removals at or before the checkpoint's step were applied before it was written
  std::size_t next_removal = 0;
  while (next_removal < removals.size() && report.resumed && removals[next_removal].first <= sys.step) ++next_removal;

  RunRecorder recorder(sys, work.string());
  if (report.resumed) recorder.restore_counts(pr.segments, pr.series_rows, pr.snapshots);

  const double wall_before = pr.wall_seconds;  // spent by earlier invocations
  auto wall_now = [&] { return wall_before + std::chrono::duration<double>(Clock::now() - t_start).count(); };
  auto checkpoint = [&] {
    pr.wall_seconds = wall_now();
    recorder.flush_segment();
    pr.segments = recorder.segments();
    pr.series_rows = recorder.series_rows();
    pr.snapshots = recorder.snapshot_count();
    pr.jam = jam.state();
    write_checkpoint(ckpt, sys, pr, scene.text);
  };
  const std::int64_t first_step = sys.step;
  const std::int64_t first_rebuild = sys.lists.rebuild_count;
  Progress progress(opt.progress, out_dir / "run.log", total, sys.size(), first_step);
  progress.note(std::string(report.resumed ? "resumed" : "started") + " '" + scene.name + "' at step " +
                std::to_string(first_step) + " of " + std::to_string(total) + ", " + std::to_string(sys.threads) +
                " threads" + (scene.path.empty() ? "" : ", scene " + scene.path));
  auto finish_report = [&](bool complete) {
    report.complete = complete;
    report.final_step = sys.step;
    report.steps = sys.step - first_step;
    report.wall_seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
    const auto active = static_cast<double>(std::count(sys.p.active.begin(), sys.p.active.end(), 1));
    if (report.steps > 0 && active > 0)
      report.ns_per_particle_step = report.wall_seconds * 1e9 / (static_cast<double>(report.steps) * active);
    report.rebuilds = sys.lists.rebuild_count - first_rebuild;
    if (active > 0) report.candidates_per_grain = static_cast<double>(sys.lists.pairs.slots()) / active;
    report.lost = sys.lost.size();
    report.jams = jam.state().jam_times.size();
    return report;
  };
  auto last_checkpoint = Clock::now();
  std::int64_t chunk = 64;
  std::int64_t last_series = -1, last_snapshot = -1;
  while (true) {
    // events due at this step, always in this order
    for (; next_removal < removals.size() && removals[next_removal].first == sys.step; ++next_removal)
      sys.remove_body(removals[next_removal].second);
    if (sys.step == jam.next_step() && !jam.update(sys)) {
      report.stop_reason = "hopper outlet jammed: " + std::to_string(scene.jam.max_taps) + " taps did not clear it";
      break;
    }
    if (every_series && sys.step == pr.next_series) {
      recorder.record_series(sys);
      last_series = sys.step;
      pr.next_series += every_series;
    }
    if (window && sys.step == pr.next_snapshot - window) {
      pr.ref_for = pr.next_snapshot;
      pr.ref_position.resize(2 * sys.size());
      for (std::size_t i = 0; i < sys.size(); ++i) {
        pr.ref_position[2 * i] = sys.p.x[i];
        pr.ref_position[2 * i + 1] = sys.p.y[i];
      }
    }
    if (every_snapshot && sys.step == pr.next_snapshot) {
      recorder.record_snapshot(sys, pr.ref_for == sys.step ? &pr.ref_position : nullptr);
      pr.ref_for = -1;
      last_snapshot = sys.step;
      pr.next_snapshot += every_snapshot;
    }
    if (every_check && sys.step == pr.next_check) {
      pr.next_check += every_check;
      if (free_stop && held_by_bed(sys, free_body)) pr.last_contact = sys.step;
      if (free_stop && sys.step - pr.last_contact >= free_steps) {
        report.stop_reason = "body " + stop.body_free + " free of the bed for " + std::to_string(stop.free_time) + " s";
        break;
      }
      if (energy_stop && kinetic_energy_criterion_met(sys, stop) && highest_grain(sys) < stop.all_below) {
        std::ostringstream why;
        if (stop.kinetic_energy_per_grain_below > 0.0)
          why << "kinetic energy below " << stop.kinetic_energy_per_grain_below << " J/m per grain";
        else
          why << "kinetic energy below " << stop.kinetic_energy_below << " J/m";
        if (stop.all_below < 1e300) why << " with every grain below " << stop.all_below << " m";
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
      progress.note("interrupted at step " + std::to_string(sys.step) + ": checkpoint written; rerun to resume");
      return finish_report(false);
    }
    if (scene.output.checkpoint_interval > 0.0 &&
        std::chrono::duration<double>(Clock::now() - last_checkpoint).count() >= scene.output.checkpoint_interval) {
      checkpoint();
      last_checkpoint = Clock::now();
      progress.note("checkpoint at step " + std::to_string(sys.step));
    }

    std::int64_t target = std::min({total, sys.step + chunk, jam.next_step()});
    if (next_removal < removals.size()) target = std::min(target, removals[next_removal].first);
    if (every_series) target = std::min(target, pr.next_series);
    if (every_snapshot) target = std::min(target, pr.next_snapshot);
    if (window && pr.next_snapshot - window > sys.step) target = std::min(target, pr.next_snapshot - window);
    if (every_check) target = std::min(target, pr.next_check);
    if (opt.interrupt_at_step > sys.step) target = std::min(target, opt.interrupt_at_step);
    const auto t0 = Clock::now();
    const std::int64_t n = target - sys.step;
    sys.advance(n);
    const double secs = std::chrono::duration<double>(Clock::now() - t0).count();
    // aim at ~0.1 s per call: responsive to signals and checkpoints, negligible overhead
    if (n == chunk && secs > 0)
      chunk = std::clamp<std::int64_t>(static_cast<std::int64_t>(static_cast<double>(n) / secs * 0.1), 1, 1 << 24);
    progress.update(sys.step, sys.time());
  }
  progress.done();

  // the final state always ends the run file, so that later stages can start from it
  if (every_series && last_series != sys.step) recorder.record_series(sys);
  if (last_snapshot != sys.step) recorder.record_snapshot(sys);

  RunInfo info;
  info.scene_text = scene.text;
  info.scene_path = scene.path;
  info.code_version = code_version();
  info.threads = sys.threads;
  info.initial_run = scene.initial_run;
  info.jam_times = jam.state().jam_times;
  info.wall_seconds = wall_now();
  info.displacement_window = window ? static_cast<double>(window) * scene.dt : 0.0;
  report.run_file = (out_dir / "run.h5").string();
  recorder.finish(sys, info, report.run_file, report.stop_reason);
  fs::remove_all(work);
  progress.note("finished at step " + std::to_string(sys.step) + " (t = " + std::to_string(sys.time()) + " s): " +
                report.stop_reason + " -> " + report.run_file);
  return finish_report(true);
}

}  // namespace dem2d
