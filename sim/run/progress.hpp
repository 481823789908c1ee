// How far a run is, said three ways: a live line on a terminal (every 0.5 s),
// a plain line on stderr when it is not a terminal (a batch job, a make log),
// and a line in DIR/run.log, both every `every` seconds of wall time (what
// LAMMPS users know as thermo output). Each line gives the simulated time,
// the step, how far towards the expected end, the rate since the previous
// line and the time left at that rate: towards the end a stop criterion
// forecasts (a pull-off's intruder clearing the bed), or "at most" the time
// to the duration when a criterion may end the run at a time nobody can
// foresee (the fill's kinetic energy). The log also says when the run starts,
// resumes, checkpoints and ends. Wall-clock only: never changes results.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <string>

#include "run/controller.hpp"

namespace dem2d {

struct ProgressOptions {
  bool terminal = false;  // stderr is a terminal: a live line there
  double every = 60.0;    // wall seconds between plain lines (stderr when not a terminal, and the log); 0: none
};

// The rate the ETA is taken from: steps per wall second over the last
// `window` seconds (from the first sample while the run is younger), so that
// a few seconds of a busy machine move the ETA by their share of the window,
// not by the ratio of the rates.
class RateWindow {
 public:
  explicit RateWindow(double window_seconds) : window_(window_seconds) {}
  void add(double seconds, std::int64_t step);
  double rate() const;  // steps per second; 0 before two samples

 private:
  struct Sample {
    double seconds;
    std::int64_t step;
  };
  double window_;
  std::deque<Sample> samples_;
};

class Progress {
 public:
  using Clock = std::chrono::steady_clock;

  Progress(const ProgressOptions& options, const std::filesystem::path& log, double dt, std::size_t particles,
           std::int64_t step);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // Whether a line is due now (cheap: call every loop pass).
  bool due() const;
  // Writes the lines that are due; `end` is the run's forecast end,
  // `physics` the state's numbers (run/thermo.hpp), appended.
  void update(std::int64_t step, double t, const EndForecast& end, const std::string& physics = "");
  // A line in the log, stamped with the date and time.
  void note(const std::string& what);
  // note(), and the same line on stderr when progress lines are on (the run's first line).
  void announce(const std::string& what);
  void done();

  // The text of a progress line (for the tests).
  // steps_per_s is shown, eta_steps_per_s (the window's) gives the ETA.
  static std::string line(double t, std::int64_t step, double dt, double steps_per_s, std::size_t particles,
                          const EndForecast& end, double eta_steps_per_s);

 private:
  struct Mark {
    Clock::time_point when;
    std::int64_t step;
  };
  double since(const Mark& m, Clock::time_point now) const;
  std::string line_since(Mark& m, Clock::time_point now, std::int64_t step, double t, const EndForecast& end);

  ProgressOptions opt_;
  std::FILE* log_;
  double dt_;
  std::size_t particles_;
  Mark term_, plain_;
  Clock::time_point start_;
  RateWindow eta_rate_;
};

// The earliest end the controllers forecast (and whether one may end it sooner).
template <class Controllers>
EndForecast forecast_end(const Controllers& controllers, const System& sys) {
  EndForecast best;
  bool sooner = false;
  for (const Controller* c : controllers) {
    EndForecast f = c->forecast(sys);
    sooner = sooner || f.may_end_sooner;
    if (f.time < best.time) best = std::move(f);
  }
  best.may_end_sooner = sooner;
  return best;
}

}  // namespace dem2d
