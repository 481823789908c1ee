#include "run/body_removals.hpp"

#include <algorithm>
#include <cmath>

#include "core/step_count.hpp"

namespace dem2d {

BodyRemovals::BodyRemovals(const Scene& scene) {
  for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    if (scene.bodies[b].remove_at >= 0.0) at_.emplace_back(steps_in(scene.bodies[b].remove_at, scene.dt), b);
  std::sort(at_.begin(), at_.end());
}

std::string BodyRemovals::act(System& sys) {
  for (; next_ < at_.size() && at_[next_].first == sys.state.step; ++next_) sys.remove_body(at_[next_].second);
  return "";
}

}  // namespace dem2d
