// Runs a scene to its end: steps the System between the steps at which its
// controllers act (run/controller.hpp: body removals, jam taps, output on the
// scene's schedule, stop criteria, the duration), checkpoints, and assembles
// the run file. Layout of the output directory:
//   DIR/run.h5, DIR/run.xdmf   written only when the run is complete
//   DIR/.run.work/             segments and checkpoint while it runs
//   DIR/run.log                how far it is: start, resume, a line every progress.every s, checkpoints,
//                              end (appended)
// Rerunning the same scene into the same DIR resumes from the checkpoint; into
// a DIR whose run.h5 is already this run's (run/finished_run.hpp), it does
// nothing; another run's is replaced only with --overwrite.
#pragma once

#include <cstdint>
#include <string>

#include "run/progress.hpp"
#include "scene/scene.hpp"

namespace dem2d {

struct RunOptions {
  std::string out_dir;
  bool fresh = false;     // discard an existing checkpoint instead of resuming
  bool overwrite = false;  // replace DIR/run.h5 and run.xdmf: a finished run (of this scene or another), or
                           // files that are not a dem2d run's
  ProgressOptions progress{};  // where and how often to say how far the run is (run/progress.hpp)
  std::string threads_why{};   // how the thread count was chosen, for the first progress line (run/thread_choice.hpp)
  // For tests: act as if interrupted once this step is reached (-1: never).
  std::int64_t interrupt_at_step = -1;
};

struct RunReport {
  bool complete = false;  // false: interrupted, checkpoint written
  bool resumed = false;
  bool already_complete = false;  // DIR/run.h5 was this run's already: nothing done (stop_reason: which run)
  std::string stop_reason;
  std::string stopped_by;  // the criterion (Controller::stop_criterion)
  std::int64_t steps = 0;        // steps advanced by this invocation
  std::int64_t final_step = 0;
  double wall_seconds = 0.0;     // of this invocation
  double ns_per_particle_step = 0.0;
  std::size_t lost = 0;
  std::size_t jams = 0;          // hopper jams detected (and tapped)
  std::int64_t rebuilds = 0;     // neighbour-list rebuilds in this invocation
  double candidates_per_grain = 0.0;  // pair slots (candidate contacts) per active grain at the end
  std::string run_file;
};

RunReport run_scene(const Scene& scene, const RunOptions& options);

// Async-signal-safe: asks a running run_scene to checkpoint and return.
void request_interrupt();

}  // namespace dem2d
