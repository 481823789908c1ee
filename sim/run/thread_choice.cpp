#include "run/thread_choice.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

namespace dem2d {

namespace {

// Below this many grains per thread a step's work is too small for its two
// barriers: one thread is faster (docs/performance.md, "Thread count").
constexpr std::size_t kMinGrainsPerThread = 800;

struct CpuTimes {
  double idle = 0.0, total = 0.0;
  bool ok = false;
};

CpuTimes read_cpu_times() {
  std::ifstream in("/proc/stat");
  std::string label;
  CpuTimes t;
  if (!(in >> label) || label != "cpu") return t;
  double v[8] = {};
  for (double& x : v) in >> x;  // user nice system idle iowait irq softirq steal
  if (!in) return t;
  for (double x : v) t.total += x;
  t.idle = v[3] + v[4];
  t.ok = true;
  return t;
}

}  // namespace

std::string threads_text(int n) { return std::to_string(n) + (n == 1 ? " thread" : " threads"); }

double free_cores_now(int cores, double seconds) {
  const CpuTimes a = read_cpu_times();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const CpuTimes b = read_cpu_times();
  if (!a.ok || !b.ok || b.total <= a.total) return cores;
  // /proc/stat counts every processor of the machine; this process may be allowed fewer
  const double machine = static_cast<double>(std::max(1u, std::thread::hardware_concurrency()));
  const double idle = machine * (b.idle - a.idle) / (b.total - a.total);
  return std::clamp(idle - (machine - cores), 0.0, static_cast<double>(cores));
}

ThreadChoice choose_threads(std::size_t grains, int cores, double free_cores) {
  const auto worth = static_cast<int>(std::max<std::size_t>(1, grains / kMinGrainsPerThread));
  const int idle = std::max(1, static_cast<int>(std::floor(free_cores + 0.5)));
  ThreadChoice c;
  c.threads = std::max(1, std::min({cores, worth, idle}));
  std::ostringstream why;
  why << threads_text(c.threads) << " (the default: ";
  if (c.threads == worth && worth < std::min(cores, idle))
    why << grains << " grains, " << kMinGrainsPerThread << " or more per thread pay for their barriers";
  else if (c.threads == idle && idle < cores)
    why << std::round(free_cores * 10.0) / 10.0 << " of the " << cores << " cores are free";
  else
    why << "all " << cores << (cores == 1 ? " core" : " cores");
  why << "; --threads N to choose)";
  c.why = why.str();
  return c;
}

}  // namespace dem2d
