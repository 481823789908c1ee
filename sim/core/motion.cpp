#include "core/motion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace dem2d {

namespace {

constexpr double kTwoPi = 2.0 * M_PI;

// Velocity at the end of a piece (the start velocity of a ramp after it).
void end_velocity(MotionKind kind, double px, double py, double duration, double& vx, double& vy) {
  switch (kind) {
    case MotionKind::constant:
    case MotionKind::ramp: vx = px, vy = py; return;
    case MotionKind::triangle: vx = -2.0 * px / duration, vy = -2.0 * py / duration; return;  // on its way back
    default: vx = vy = 0.0; return;                                                              // hold, sine
  }
}

}  // namespace

MotionSchedule::MotionSchedule(const std::vector<MotionSegment>& segments, int repeat) {
  if (repeat < 1) throw std::invalid_argument("repeat = " + std::to_string(repeat) + ": must be >= 1");
  double t = 0.0, x = 0.0, y = 0.0, vx = 0.0, vy = 0.0;
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
      for (int c = 0; c < count; ++c) {
        Piece p{s.kind, t, duration, x, y, vx, vy, cyclic ? s.ax : s.vx, cyclic ? s.ay : s.vy};
        pieces_.push_back(p);
        if (s.kind == MotionKind::constant && std::isfinite(duration)) {
          x += s.vx * duration;
          y += s.vy * duration;
        } else if (s.kind == MotionKind::ramp) {
          x += 0.5 * (vx + s.vx) * duration;
          y += 0.5 * (vy + s.vy) * duration;
        }  // hold, a whole cycle: back where it started
        end_velocity(s.kind, p.px, p.py, duration, vx, vy);
        t += duration;
      }
    }
  end_ = t;
  x_end_ = x;
  y_end_ = y;
}

MotionSchedule::State MotionSchedule::at(double t) const {
  if (pieces_.empty() || t >= end_) return {x_end_, y_end_, 0.0, 0.0};
  t = std::max(t, 0.0);
  // the last piece starting at or before t
  const auto it = std::upper_bound(pieces_.begin(), pieces_.end(), t, [](double v, const Piece& p) { return v < p.t0; });
  const Piece& p = *(it == pieces_.begin() ? it : it - 1);
  const double tau = t - p.t0, T = p.duration;
  State s{p.x0, p.y0, 0.0, 0.0};
  switch (p.kind) {
    case MotionKind::hold: break;
    case MotionKind::constant:
      s.x += p.px * tau, s.y += p.py * tau;
      s.vx = p.px, s.vy = p.py;
      break;
    case MotionKind::ramp: {
      const double fx = (p.px - p.v0x) / T, fy = (p.py - p.v0y) / T;  // acceleration
      s.x += p.v0x * tau + 0.5 * fx * tau * tau;
      s.y += p.v0y * tau + 0.5 * fy * tau * tau;
      s.vx = p.v0x + fx * tau, s.vy = p.v0y + fy * tau;
      break;
    }
    case MotionKind::sine: {
      const double w = kTwoPi / T, c = 0.5 * (1.0 - std::cos(w * tau)), d = 0.5 * w * std::sin(w * tau);
      s.x += p.px * c, s.y += p.py * c;
      s.vx = p.px * d, s.vy = p.py * d;
      break;
    }
    case MotionKind::triangle: {
      const bool out = tau < 0.5 * T;
      const double u = tau / T, c = out ? 2.0 * u : 2.0 * (1.0 - u), d = (out ? 2.0 : -2.0) / T;
      s.x += p.px * c, s.y += p.py * c;
      s.vx = p.px * d, s.vy = p.py * d;
      break;
    }
  }
  return s;
}

std::vector<double> MotionSchedule::corners() const {
  std::vector<double> out;
  for (const Piece& p : pieces_) out.push_back(p.t0);
  out.push_back(end_);
  return out;
}

}  // namespace dem2d
