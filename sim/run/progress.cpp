#include "run/progress.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>

namespace dem2d {

namespace {

constexpr double kTerminalSeconds = 0.5;
constexpr double kEtaWindowSeconds = 120.0;  // wall seconds the ETA's rate is averaged over

std::string format_duration(double seconds) {
  const auto s = static_cast<long long>(std::min(seconds, 1e9));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%lld:%02lld:%02lld", s / 3600, s / 60 % 60, s % 60);
  return buf;
}

}  // namespace

void RateWindow::add(double seconds, std::int64_t step) {
  samples_.push_back({seconds, step});
  // keep the newest sample at least `window` old: the rate spans the whole window
  while (samples_.size() > 2 && seconds - samples_[1].seconds >= window_) samples_.pop_front();
}

double RateWindow::rate() const {
  if (samples_.size() < 2) return 0.0;
  const Sample &a = samples_.front(), &b = samples_.back();
  return b.seconds > a.seconds ? static_cast<double>(b.step - a.step) / (b.seconds - a.seconds) : 0.0;
}

Progress::Progress(const ProgressOptions& options, const std::filesystem::path& log, double dt,
                   std::size_t particles, std::int64_t step)
    : opt_(options), log_(std::fopen(log.string().c_str(), "a")), dt_(dt), particles_(particles),
      term_{Clock::now(), step}, plain_{Clock::now(), step}, start_(Clock::now()), eta_rate_(kEtaWindowSeconds) {
  eta_rate_.add(0.0, step);
}

Progress::~Progress() {
  if (log_) std::fclose(log_);
}

double Progress::since(const Mark& m, Clock::time_point now) const {
  return std::chrono::duration<double>(now - m.when).count();
}

bool Progress::due() const {
  const auto now = Clock::now();
  return (opt_.terminal && since(term_, now) >= kTerminalSeconds) || (opt_.every > 0.0 && since(plain_, now) >= opt_.every);
}

std::string Progress::line(double t, std::int64_t step, double dt, double steps_per_s, std::size_t particles,
                           const EndForecast& end, double eta_steps_per_s) {
  const double left = std::max(0.0, end.time - t);  // simulated seconds
  const double eta = eta_steps_per_s > 0.0 ? left / dt / eta_steps_per_s : INFINITY;
  const double fraction = end.time > 0.0 ? std::min(1.0, t / end.time) : 1.0;
  char buf[320];
  if (std::isfinite(end.time))
    std::snprintf(buf, sizeof buf,
                  "t = %.6g s  step %lld  %.1f %% of %.6g s (%s)  %.3g steps/s  %.3g particle-steps/s  ETA %s%s", t,
                  static_cast<long long>(step), 100.0 * fraction, end.time, end.what.c_str(), steps_per_s,
                  steps_per_s * static_cast<double>(particles), end.may_end_sooner ? "at most " : "",
                  std::isfinite(eta) ? format_duration(eta).c_str() : "?");
  else
    std::snprintf(buf, sizeof buf, "t = %.6g s  step %lld  %.3g steps/s  %.3g particle-steps/s", t,
                  static_cast<long long>(step), steps_per_s, steps_per_s * static_cast<double>(particles));
  return buf;
}

// The rate shown is averaged since the mark, which moves to now; the ETA's over the window.
std::string Progress::line_since(Mark& m, Clock::time_point now, std::int64_t step, double t,
                                 const EndForecast& end) {
  const double steps_per_s = static_cast<double>(step - m.step) / std::max(since(m, now), 1e-9);
  m = {now, step};
  eta_rate_.add(std::chrono::duration<double>(now - start_).count(), step);
  return line(t, step, dt_, steps_per_s, particles_, end, eta_rate_.rate());
}

void Progress::update(std::int64_t step, double t, const EndForecast& end, const std::string& physics) {
  const auto now = Clock::now();
  const std::string more = physics.empty() ? "" : "  " + physics;
  if (opt_.terminal && since(term_, now) >= kTerminalSeconds) {
    std::fprintf(stderr, "\r[dem2d] %s%s   ", line_since(term_, now, step, t, end).c_str(), more.c_str());
    std::fflush(stderr);
  }
  if (opt_.every > 0.0 && since(plain_, now) >= opt_.every) {
    const std::string text = line_since(plain_, now, step, t, end) + more;
    if (!opt_.terminal) std::fprintf(stderr, "[dem2d] %s\n", text.c_str());
    note(text);
  }
}

void Progress::note(const std::string& what) {
  if (!log_) return;
  const std::time_t now = std::time(nullptr);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%d %H:%M:%S", std::localtime(&now));
  std::fprintf(log_, "%s %s\n", stamp, what.c_str());
  std::fflush(log_);
}

void Progress::announce(const std::string& what) {
  if (opt_.terminal || opt_.every > 0.0) std::fprintf(stderr, "[dem2d] %s\n", what.c_str());
  note(what);
}

void Progress::done() {
  if (opt_.terminal) std::fprintf(stderr, "\n");
}

}  // namespace dem2d
