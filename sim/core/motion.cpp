#include "core/motion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace dem2d {

namespace {

constexpr double kTwoPi = 2.0 * M_PI;
using Coords = std::array<double, 3>;

// Rates at the end of a piece (the start rates of a ramp after it).
Coords end_rates(MotionKind kind, const Coords& param, double duration) {
  Coords v{};
  for (int c = 0; c < 3; ++c) switch (kind) {
      case MotionKind::constant:
      case MotionKind::ramp: v[c] = param[c]; break;
      case MotionKind::triangle: v[c] = -2.0 * param[c] / duration; break;  // on its way back
      default: break;                                                       // hold, sine
    }
  return v;
}

}  // namespace

std::int64_t motion_pieces(const std::vector<MotionSegment>& segments, std::int64_t repeat) {
  std::int64_t run = 0;
  for (const MotionSegment& s : segments)
    run += s.kind == MotionKind::sine || s.kind == MotionKind::triangle ? std::max(s.cycles, 0) : 1;
  // (each factor at most kMaxMotionPieces where it matters: no overflow below that)
  return run > 0 && repeat > kMaxMotionPieces / run ? kMaxMotionPieces + 1 : run * repeat;
}

MotionSchedule::MotionSchedule(const std::vector<MotionSegment>& segments, int repeat) {
  if (repeat < 1) throw std::invalid_argument("repeat = " + std::to_string(repeat) + ": must be >= 1");
  if (const std::int64_t n = motion_pieces(segments, repeat); n > kMaxMotionPieces)
    throw std::invalid_argument(std::to_string(repeat) + " runs of the motion make more than " +
                                std::to_string(kMaxMotionPieces) + " pieces (cycles included)");
  double t = 0.0;
  Coords at{}, v{};
  for (int run = 0; run < repeat; ++run)
    for (std::size_t k = 0; k < segments.size(); ++k) {
      const MotionSegment& s = segments[k];
      const std::string which = "motion[" + std::to_string(k) + "]";
      const bool cyclic = s.kind == MotionKind::sine || s.kind == MotionKind::triangle;
      const double duration = cyclic ? s.period : s.duration;
      if (!(duration > 0.0)) throw std::invalid_argument(which + ": its duration or period must be > 0");
      if (std::isinf(duration) && (k + 1 != segments.size() || repeat != 1 || s.kind != MotionKind::constant))
        throw std::invalid_argument(which + ": only a last constant segment, not repeated, may last for ever");
      if (cyclic && s.cycles < 1) throw std::invalid_argument(which + ": cycles must be >= 1");
      const int count = cyclic ? s.cycles : 1;
      const Coords param = cyclic ? Coords{s.ax, s.ay, s.aw} : Coords{s.vx, s.vy, s.w};
      turns_ = turns_ || param[2] != 0.0;
      for (int c = 0; c < count; ++c) {
        pieces_.push_back({s.kind, t, duration, at, v, param});
        for (int i = 0; i < 3; ++i)
          if (s.kind == MotionKind::constant && std::isfinite(duration))
            at[i] += param[i] * duration;
          else if (s.kind == MotionKind::ramp)
            at[i] += 0.5 * (v[i] + param[i]) * duration;
        // (hold, a whole cycle: back where it started)
        v = end_rates(s.kind, param, duration);
        t += duration;
      }
    }
  end_ = t;
  end_at_ = at;
}

MotionSchedule::State MotionSchedule::at(double t) const {
  if (pieces_.empty() || t >= end_) return {end_at_[0], end_at_[1], 0.0, 0.0, end_at_[2], 0.0};
  t = std::max(t, 0.0);
  // the last piece starting at or before t
  const auto it = std::upper_bound(pieces_.begin(), pieces_.end(), t, [](double v, const Piece& p) { return v < p.t0; });
  const Piece& p = *(it == pieces_.begin() ? it : it - 1);
  const double tau = t - p.t0, T = p.duration;
  Coords d = p.start, v{};
  for (int c = 0; c < 3; ++c) {  // (each product grouped as its formula reads)
    const double a = p.param[c];
    switch (p.kind) {
      case MotionKind::hold: break;
      case MotionKind::constant:
        d[c] += a * tau;
        v[c] = a;
        break;
      case MotionKind::ramp: {
        const double f = (a - p.v0[c]) / T;  // the rate's rate of change
        d[c] += p.v0[c] * tau + 0.5 * f * tau * tau;
        v[c] = p.v0[c] + f * tau;
        break;
      }
      case MotionKind::sine: {
        const double w = kTwoPi / T;
        d[c] += a * (0.5 * (1.0 - std::cos(w * tau)));
        v[c] = a * (0.5 * w * std::sin(w * tau));
        break;
      }
      case MotionKind::triangle: {
        const bool out = tau < 0.5 * T;
        const double u = tau / T;
        d[c] += a * (out ? 2.0 * u : 2.0 * (1.0 - u));
        v[c] = a * ((out ? 2.0 : -2.0) / T);
        break;
      }
    }
  }
  return {d[0], d[1], v[0], v[1], d[2], v[2]};
}

std::vector<double> MotionSchedule::corners() const {
  std::vector<double> out;
  for (const Piece& p : pieces_) out.push_back(p.t0);
  out.push_back(end_);
  return out;
}

}  // namespace dem2d
