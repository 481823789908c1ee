#include "common/snapshot_source.hpp"

#include <algorithm>

#include "common/snapshot_loop.hpp"
#include "common/stage_error.hpp"
#include "runfile/h5.hpp"

namespace dem2d::analysis {

std::size_t SnapshotSource::body_with_role(std::string_view role) const {
  const std::vector<std::string>& roles = body_roles();
  for (std::size_t b = 0; b < roles.size(); ++b)
    if (roles[b] == role) return b;
  throw StageError(path() + ": " + no_body_with_role(role, body_names(), roles));
}

bool RunFileSource::has_displacements() const {
  return run_.displacement_window() > 0.0 && h5::exists(run_.file(), "snapshots/displacement");
}

const std::vector<double>& MemorySource::snapshot_times() const {
  if (times_.size() != snaps.size()) {
    times_.clear();
    for (const Snapshot& s : snaps) times_.push_back(s.time);
  }
  return times_;
}

const std::vector<std::string>& MemorySource::body_names() const {
  if (names_.empty() && !snaps.empty())
    for (const Body& b : snaps.front().bodies) names_.push_back(b.name);
  return names_;
}

const std::vector<std::string>& MemorySource::body_roles() const {
  if (roles_.empty() && !snaps.empty())
    for (const Body& b : snaps.front().bodies) roles_.push_back(b.role);
  return roles_;
}

std::vector<Body> MemorySource::body_track(std::size_t b) const {
  std::vector<Body> out;
  for (const Snapshot& s : snaps) out.push_back(s.bodies.at(b));
  return out;
}

std::vector<std::size_t> spread_over(const std::vector<std::size_t>& ks, std::size_t count) {
  std::vector<std::size_t> out;
  if (count == 0 || ks.empty()) return out;
  for (std::size_t q = 0; q < count; ++q) {
    const std::size_t at = count == 1 ? 0 : q * (ks.size() - 1) / (count - 1);
    if (out.empty() || out.back() != ks[at]) out.push_back(ks[at]);
  }
  return out;
}

std::vector<std::size_t> every_kth(std::size_t snapshots, std::size_t every) {
  std::vector<std::size_t> out;
  if (snapshots == 0) return out;
  for (std::size_t k = 0; k < snapshots; k += std::max<std::size_t>(every, 1)) out.push_back(k);
  if (out.back() != snapshots - 1) out.push_back(snapshots - 1);
  return out;
}

}  // namespace dem2d::analysis
