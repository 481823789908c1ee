// Scheduled motion of a body: its displacement, its turn and their rates as
// closed-form functions of time, from a list of segments the scene gives
// (`[[body]] motion = [...]`, docs/scene_format.md). Three coordinates move
// alike, by the same formulas: x, y (m) of the body's pivot and the angle
// (rad, counter-clockwise) the body has turned about it.
//
//   hold       at rest for `duration`
//   constant   at `velocity` and `angular_velocity` for `duration` (the last segment may omit it: for ever)
//   ramp       rates changing linearly from the ones at its start to the given ones over `duration`
//   sine       `cycles` cycles of period `period`: d(tau) = A (1 - cos(2 pi tau/P))/2,
//              out to the peak displacement A (`amplitude`, `angle`) and back, at rest at both ends
//   triangle   the same path at constant rate 2|A|/P: out in P/2, back in P/2
//
// and `repeat` (>= 1) runs of the whole list, each starting where the last
// ended. After the schedule the body holds still. The schedule is unrolled
// into pieces (one per segment, cycle and run) whose start times and start
// displacements are sums of the exact per-piece displacements (v T,
// (v0 + v1) T/2, 0 for a cycle), so a corner is where the formulas put it,
// with no accumulated integration error.
//
// A new kind is a new enumerator with its formulas in motion.cpp (position,
// velocity, end velocity and displacement) plus its keys in kMotionKinds.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

namespace dem2d {

enum class MotionKind { hold, constant, ramp, sine, triangle };

// What a scene segment holds (SI). Unused fields stay 0.
struct MotionSegment {
  MotionKind kind = MotionKind::hold;
  double duration = 0.0;       // s (hold, constant, ramp); +inf: a last constant segment for ever
  double vx = 0.0, vy = 0.0;   // m/s: constant's velocity, ramp's final velocity
  double w = 0.0;              // rad/s: constant's angular velocity, ramp's final one
  double ax = 0.0, ay = 0.0;   // m: sine's and triangle's peak displacement
  double aw = 0.0;             // rad: sine's and triangle's peak angle
  double period = 0.0;         // s: one cycle
  int cycles = 1;              // sine, triangle
};

// The kinds a scene may name and the keys each takes (besides `kind`).
struct MotionKindSpec {
  std::string_view name;
  MotionKind kind;
  bool velocity, duration, amplitude, period, cycles;  // which keys it takes (all required but
                                                       // a last constant's duration and cycles = 1;
                                                       // velocity and amplitude: or their turns,
                                                       // angular_velocity and angle, or both)
};
inline constexpr std::array<MotionKindSpec, 5> kMotionKinds{{
    {"hold", MotionKind::hold, false, true, false, false, false},
    {"constant", MotionKind::constant, true, true, false, false, false},
    {"ramp", MotionKind::ramp, true, true, false, false, false},
    {"sine", MotionKind::sine, false, false, true, true, true},
    {"triangle", MotionKind::triangle, false, false, true, true, true},
}};

// The row of kMotionKinds for a kind, and for a name (nullptr: none).
constexpr const MotionKindSpec& motion_kind(MotionKind kind) {
  for (const MotionKindSpec& s : kMotionKinds)
    if (s.kind == kind) return s;
  return kMotionKinds[0];
}
constexpr const MotionKindSpec* motion_kind_named(std::string_view name) {
  for (const MotionKindSpec& s : kMotionKinds)
    if (s.name == name) return &s;
  return nullptr;
}

// A schedule unrolls its segments' cycles and runs into pieces (~100 bytes each): at most this many.
inline constexpr std::int64_t kMaxMotionPieces = 1'000'000;
// The pieces of `repeat` runs of the segments (each cycle of a sine or triangle one piece).
std::int64_t motion_pieces(const std::vector<MotionSegment>& segments, std::int64_t repeat);

class MotionSchedule {
 public:
  MotionSchedule() = default;
  // Throws std::invalid_argument (naming the segment) on a schedule that
  // cannot run: a duration or period <= 0, an endless segment before the end
  // or repeated, more than kMaxMotionPieces pieces.
  MotionSchedule(const std::vector<MotionSegment>& segments, int repeat);

  struct State {
    double x = 0.0, y = 0.0;    // displacement from the start (m)
    double vx = 0.0, vy = 0.0;  // velocity (m/s)
    double angle = 0.0;         // turned since the start (rad, counter-clockwise)
    double omega = 0.0;         // angular velocity (rad/s)
  };
  // At time t (s); t < 0 is the start.
  State at(double t) const;
  bool empty() const { return pieces_.empty(); }
  bool turns() const { return turns_; }  // whether any segment turns the body
  // When each piece starts (s): the schedule's corners, then its end.
  std::vector<double> corners() const;

 private:
  using Coords = std::array<double, 3>;  // x (m), y (m), angle (rad); or their rates
  struct Piece {
    MotionKind kind;
    double t0, duration;   // s
    Coords start;          // where it starts
    Coords v0;             // rates at its start (ramp)
    Coords param;          // constant, ramp: the rates; sine, triangle: the amplitudes
  };
  std::vector<Piece> pieces_;
  double end_ = 0.0;
  Coords end_at_{};
  bool turns_ = false;
};

}  // namespace dem2d
