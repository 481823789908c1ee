#include "run/run.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "core/version.hpp"
#include "engine/kernel_sets.hpp"
#include "engine/system.hpp"
#include "run/body_removals.hpp"
#include "run/checkpoint.hpp"
#include "run/finished_run.hpp"
#include "run/jam_control.hpp"
#include "run/output_control.hpp"
#include "run/output_dir.hpp"
#include "run/progress.hpp"
#include "run/stop_criteria.hpp"
#include "run/thermo.hpp"
#include "run/thread_choice.hpp"
#include "run/thread_governor.hpp"
#include "writer/run_file.hpp"

namespace dem2d {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

std::atomic<bool> g_interrupt{false};
static_assert(std::atomic<bool>::is_always_lock_free);

}  // namespace

void request_interrupt() { g_interrupt.store(true); }

RunReport run_scene(const Scene& scene, const RunOptions& opt) {
  g_interrupt.store(false);
  const auto t_start = Clock::now();
  const OutputDir folder(opt.out_dir, scene.initial_run, opt.overwrite);  // checked and locked for this run
  const fs::path out_dir = folder.path();
  const fs::path work = folder.work();
  const std::string ckpt = (work / "checkpoint.h5").string();

  RunReport report;
  const bool resume = !opt.fresh && fs::exists(ckpt);
  // A checkpoint that cannot be resumed from: say so, and how to start over.
  const auto unusable = [&](const std::string& why) {
    return std::runtime_error(why + "; rerun with --fresh to discard the unfinished run in " + work.string() +
                              " and start over");
  };
  std::string ckpt_scene;
  if (resume) {
    try {
      ckpt_scene = checkpoint_scene_text(ckpt);
    } catch (const std::exception& e) {
      throw unusable(std::string("cannot resume: ") + e.what());
    }
  }
  if (resume && ckpt_scene != scene.text)
    throw unusable(ckpt + " was written by a different scene or dem2d version");
  const Rerun rerun = resume ? Rerun{} : check_rerun(out_dir, scene, code_version(), opt.overwrite);
  if (rerun.nothing_to_do) {
    report.complete = report.already_complete = true;
    report.run_file = (out_dir / "run.h5").string();
    report.stop_reason = rerun.finished;
    return report;
  }
  System sys(scene);
  std::error_code ec;
  // an unfinished run that left no checkpoint (killed before its first one, or checkpoint_interval = 0)
  const bool lost_work = !resume && !opt.fresh && fs::exists(work, ec) && !fs::is_empty(work, ec);
  if (!resume) folder.fresh_work();
  RunRecorder recorder(sys, work.string());
  // what acts at given steps, in the order it acts within a step
  BodyRemovals removals(scene);
  JamController jam(scene.jam, sys);
  OutputController output(scene, recorder);
  StopCriteria criteria(scene, sys);
  DurationLimit duration(scene);
  const std::array<Controller*, 5> controllers{&removals, &jam, &output, &criteria, &duration};

  double wall_before = 0.0;  // spent by earlier invocations
  if (resume) {
    try {
      wall_before = read_checkpoint(ckpt, sys, controllers);
    } catch (const std::exception& e) {
      throw unusable(std::string("cannot resume: ") + e.what());
    }
    report.resumed = true;
  }
  auto wall_now = [&] { return wall_before + std::chrono::duration<double>(Clock::now() - t_start).count(); };
  auto checkpoint = [&] { write_checkpoint(ckpt, sys, controllers, wall_now(), scene.text); };
  const std::int64_t first_step = sys.state.step;
  const std::int64_t first_rebuild = sys.state.lists.rebuild_count;
  const std::int64_t total = duration.last_step();
  Progress progress(opt.progress, out_dir / "run.log", scene.dt, sys.size(), first_step);
  std::string threads = opt.threads_why.empty() ? threads_text(sys.config.threads) : opt.threads_why;
  if (sys.config.threads < scene.threads)  // OpenMP gave a smaller team (system.cpp: config_of)
    threads = threads_text(sys.config.threads) + ", of " + std::to_string(scene.threads) +
              " asked: OpenMP runs parallel regions with fewer (OMP_MAX_ACTIVE_LEVELS, OMP_THREAD_LIMIT)";
  progress.announce(std::string(report.resumed ? "resumed" : "started") + " '" + scene.name + "' at step " +
                    std::to_string(first_step) + " of " + std::to_string(total) + ", " + threads + ", " +
                    kernel_description(scene.effects, scene.generic_kernel) +
                    (scene.path.empty() ? "" : ", scene " + scene.path) +
                    (lost_work ? "; the unfinished run in " + work.string() +
                                     " left no checkpoint (killed before its first, or checkpoint_interval = 0): "
                                     "started again from step 0"
                               : ""));
  if (!rerun.replacing.empty()) progress.announce(rerun.replacing);
  auto finish_report = [&](bool complete) {
    report.complete = complete;
    report.final_step = sys.state.step;
    report.steps = sys.state.step - first_step;
    report.wall_seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
    const auto active = static_cast<double>(std::count(sys.state.p.active.begin(), sys.state.p.active.end(), 1));
    if (report.steps > 0 && active > 0)
      report.ns_per_particle_step = report.wall_seconds * 1e9 / (static_cast<double>(report.steps) * active);
    report.rebuilds = sys.state.lists.rebuild_count - first_rebuild;
    if (active > 0) report.candidates_per_grain = static_cast<double>(sys.state.lists.pairs.slots()) / active;
    report.lost = sys.state.lost.size();
    report.jams = jam.jam_times().size();
    return report;
  };
  auto last_checkpoint = Clock::now();
  std::int64_t chunk = 64;
  ThreadGovernor governor(sys.config.threads);  // fewer threads while other work takes the cores
  while (report.stop_reason.empty()) {
    for (Controller* c : controllers)
      if (c->next_step() == sys.state.step && !(report.stop_reason = c->act(sys)).empty()) {
        report.stopped_by = c->stop_criterion();
        break;
      }
    if (!report.stop_reason.empty()) break;
    if (g_interrupt.load() || sys.state.step == opt.interrupt_at_step) {
      checkpoint();
      progress.done();
      progress.note("interrupted at step " + std::to_string(sys.state.step) + ": checkpoint written; rerun to resume");
      return finish_report(false);
    }
    if (scene.output.checkpoint_interval > 0.0 &&
        std::chrono::duration<double>(Clock::now() - last_checkpoint).count() >= scene.output.checkpoint_interval) {
      checkpoint();
      last_checkpoint = Clock::now();
      progress.note("checkpoint at step " + std::to_string(sys.state.step));
    }

    std::int64_t target = sys.state.step + chunk;
    for (const Controller* c : controllers) target = std::min(target, c->next_step());
    if (opt.interrupt_at_step > sys.state.step) target = std::min(target, opt.interrupt_at_step);
    if (const std::int64_t cap = governor.step_cap(); cap < target - sys.state.step) target = sys.state.step + cap;
    sys.set_threads(governor.threads());
    const auto t0 = Clock::now();
    const std::int64_t n = target - sys.state.step;
    sys.advance(n);
    const double secs = std::chrono::duration<double>(Clock::now() - t0).count();
    if (const std::string change = governor.record(n, secs); !change.empty()) progress.announce(change);
    // aim at ~0.1 s per call: responsive to signals and checkpoints, negligible overhead
    if (n == chunk && secs > 0)
      chunk = std::clamp<std::int64_t>(static_cast<std::int64_t>(static_cast<double>(n) / secs * 0.1), 1, 1 << 24);
    if (progress.due()) progress.update(sys.state.step, sys.time(), forecast_end(controllers, sys), thermo_text(sys));
  }
  progress.done();
  for (Controller* c : controllers) c->finish(sys);

  RunInfo info;
  info.scene = &scene;
  info.stopped_by = report.stopped_by;
  info.scene_text = scene.text;
  info.scene_path = scene.path;
  info.code_version = code_version();
  info.threads = sys.config.threads;
  info.initial_run = scene.initial_run;
  info.jam_times = jam.jam_times();
  info.wall_seconds = wall_now();
  info.displacement_window = output.displacement_window(scene.dt);
  report.run_file = (out_dir / "run.h5").string();
  recorder.finish(sys, info, report.run_file, report.stop_reason);
  folder.remove_work();
  progress.note("finished at step " + std::to_string(sys.state.step) + " (t = " + std::to_string(sys.time()) + " s): " +
                report.stop_reason + " -> " + report.run_file);
  return finish_report(true);
}

}  // namespace dem2d
