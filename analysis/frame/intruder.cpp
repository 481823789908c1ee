#include "frame/intruder.hpp"

namespace dem2d::analysis {

Intruder intruder_of(const Body& b) {
  const Vec2 c = b.centre();
  return {c.x, c.y, b.xmin(), b.xmax(), b.ymax()};
}

namespace {
template <class Run>
Pull pull_in(const Run& run) {
  const std::size_t b = run.body_with_role("intruder");
  return {b, run.body_velocities().at(b)};
}
}  // namespace

Pull pull_of(const SnapshotSource& run) { return pull_in(run); }
Pull pull_of(const RunReader& run) { return pull_in(run); }

}  // namespace dem2d::analysis
