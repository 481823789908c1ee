// What the stages that walk a run snapshot by snapshot (cg, network) read of
// it, behind one interface: a run file (RunFileSource, through the checking
// RunReader), or snapshots made in memory with a known answer (the
// planted-truth suite, tests/planted/), so that both go through the very same
// computation.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

class SnapshotSource {
 public:
  virtual ~SnapshotSource() = default;
  // for messages: the run file's path, or what made the snapshots
  virtual const std::string& path() const = 0;
  virtual const std::vector<double>& snapshot_times() const = 0;  // (s) [S], increasing
  std::size_t snapshots() const { return snapshot_times().size(); }
  virtual Snapshot snapshot(std::size_t k) const = 0;
  // PIV-like displacements (docs/run_file.md): the window (s; 0: none), whether
  // the run has them, and the grains' displacements over it before snapshot k (m)
  virtual double displacement_window() const = 0;
  virtual bool has_displacements() const = 0;
  virtual std::vector<Vec2> displacement(std::size_t k) const = 0;
  virtual const std::vector<std::string>& body_names() const = 0;
  virtual const std::vector<std::string>& body_roles() const = 0;
  virtual std::vector<Vec2> body_velocities() const = 0;  // prescribed (m/s) [B]
  // body b at every snapshot, without reading the grains
  virtual std::vector<Body> body_track(std::size_t b) const = 0;
  // the body with this role; a StageError naming the run's bodies and roles if none
  std::size_t body_with_role(std::string_view role) const;
};

// A run file.
class RunFileSource : public SnapshotSource {
 public:
  explicit RunFileSource(const std::string& path) : run_(path) {}
  const RunReader& run() const { return run_; }
  const std::string& path() const override { return run_.path(); }
  const std::vector<double>& snapshot_times() const override { return run_.snapshot_times(); }
  Snapshot snapshot(std::size_t k) const override { return run_.snapshot(k); }
  double displacement_window() const override { return run_.displacement_window(); }
  bool has_displacements() const override;
  std::vector<Vec2> displacement(std::size_t k) const override { return run_.displacement(k); }
  const std::vector<std::string>& body_names() const override { return run_.body_names(); }
  const std::vector<std::string>& body_roles() const override { return run_.body_roles(); }
  std::vector<Vec2> body_velocities() const override { return run_.body_velocities(); }
  std::vector<Body> body_track(std::size_t b) const override { return run_.body_rows("snapshots", b); }

 private:
  RunReader run_;
};

// Snapshots held in memory (the planted-truth suite): every snapshot has the
// same grains and bodies; displacements given per snapshot (empty: none).
class MemorySource : public SnapshotSource {
 public:
  std::string name = "snapshots in memory";
  std::vector<Snapshot> snaps;
  std::vector<std::vector<Vec2>> displacements;  // [S][N], or empty
  double window = 0.0;                           // s
  std::vector<Vec2> velocities;                  // [B] prescribed body velocities

  const std::string& path() const override { return name; }
  const std::vector<double>& snapshot_times() const override;
  Snapshot snapshot(std::size_t k) const override { return snaps.at(k); }
  double displacement_window() const override { return window; }
  bool has_displacements() const override { return !displacements.empty(); }
  std::vector<Vec2> displacement(std::size_t k) const override { return displacements.at(k); }
  const std::vector<std::string>& body_names() const override;
  const std::vector<std::string>& body_roles() const override;
  std::vector<Vec2> body_velocities() const override { return velocities; }
  std::vector<Body> body_track(std::size_t b) const override;

 private:
  // filled from snaps on first use
  mutable std::vector<double> times_;
  mutable std::vector<std::string> names_, roles_;
};

}  // namespace dem2d::analysis
