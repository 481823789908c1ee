// Keeps a run on several threads from collapsing when other work takes its
// cores. Every step waits at barriers for all of its threads; a thread whose
// core is taken holds the others for a scheduler time slice, and two threads
// beside one busy process ran a small scene 10-50x slower than one thread.
// The governor times the run loop's calls of System::advance and, now and
// then, runs a short stretch on the other thread count (one thread while on
// all, all while on one): the faster one is kept, and a change is said in the
// log. The results never depend on it (the same bits on any thread count,
// System::set_threads).
//
// A probe starts with a short call (kFirstCall at the kept pace) and ends
// there when it is already slower by more than the margin: a probe of two
// threads on a taken core costs that call (~10x kFirstCall), not a whole
// probe at the collapsed pace; one that is faster runs kProbeSeconds to
// confirm. The cost where nothing competes: that first call at one
// thread's pace every probe period, which doubles from kFirstPeriod to
// kLongestPeriod while the probes lose (the first probe comes after
// kStartPeriod, so that a short run is rescued too).
#pragma once

#include <cstdint>
#include <string>

namespace dem2d {

class ThreadGovernor {
 public:
  static constexpr double kStartPeriod = 0.02;    // wall seconds from the start to the first probe
  static constexpr double kFirstPeriod = 0.1;     // ... and on a new count before its first probe
  static constexpr double kLongestPeriod = 64.0;  // ... and at most, while probes lose
  static constexpr double kProbeSeconds = 0.1;    // a probe's length (wall s; one or a few calls of advance)
  static constexpr double kWindowSeconds = 0.25;  // the pace of the kept count: its last calls over this
  static constexpr double kFirstCall = 0.002;     // a probe's first call: the steps the kept count does in this
  static constexpr double kMargin = 0.1;          // a probe wins when faster by more than this fraction, and
                                                  // loses at once when slower by more than it

  // threads: the most the run may use (SystemConfig::threads); 1 turns it off.
  explicit ThreadGovernor(int threads);

  // The thread count for the next call of advance, and the most steps it
  // should take: a probe starts with a short call, so that a probe of a count
  // that collapses costs little, and a call on the kept count ends when the
  // next probe is due.
  int threads() const { return current_; }
  std::int64_t step_cap() const;
  // After a call of advance of `steps` steps in `seconds` (wall) on threads():
  // "" or, when the kept count changed, a line for the log saying why.
  std::string record(std::int64_t steps, double seconds);

 private:
  struct Pace {  // steps and wall seconds summed over recent calls
    double steps = 0.0, seconds = 0.0;
    double per_step() const { return seconds / steps; }
  };
  int max_;
  int kept_, current_;        // the count kept; the count of the next call (kept_ or the probe's)
  double period_ = kStartPeriod;
  double since_probe_ = 0.0;  // wall seconds on kept_ since the last probe
  Pace window_, probe_;
};

}  // namespace dem2d
