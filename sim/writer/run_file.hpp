// The run file: one HDF5 file per run (layout in docs/run_file.md).
//
// A half-written file must never look complete, and a killed run must be able
// to resume. So records are buffered in memory and written as complete, closed
// segment files (work_dir/segment_NNNNNN.h5, each written under a .tmp name and
// renamed). At the end, `finish` assembles the header and all segments into
// out_path + ".tmp" and renames it to out_path, with an XDMF file beside it for
// ParaView. A file named out_path therefore exists only once it is complete.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "engine/system.hpp"
#include "runfile/h5.hpp"
#include "runfile/run_format.hpp"

namespace dem2d {

// Header data, written as root attributes.
struct RunInfo {
  const Scene* scene = nullptr;    // the validated scene, written as /parameters (required)
  std::string stopped_by;          // the criterion that ended the run (Controller::stop_criterion)
  std::string scene_text, scene_path, code_version;  // code_version: core/version.hpp
  int threads = 1;
  std::string initial_run;         // run file the grains came from ("" if none)
  std::vector<double> jam_times;   // times (s) the hopper outlet was found jammed and tapped
  double wall_seconds = 0.0;       // wall-clock time of the whole run, over all its invocations (s)
  double displacement_window = 0.0;  // (s) of /snapshots/displacement, 0 if not recorded
};


// The grains that left the domain, as /lost/{id, step, x, y} in f (also used
// by checkpoints).
void write_lost(const h5::File& f, const std::vector<LostParticle>& lost);

class RunRecorder {
 public:
  RunRecorder(const System& sys, std::string work_dir);  // work_dir must exist

  // Appends one time-series row, then resets the body force sums (sys.reset_body_sums()).
  void record_series(System& sys);
  // Appends one snapshot: every particle (inactive ones flagged) and every
  // touching contact. `reference`: the positions (x0, y0, x1, y1, ...) some
  // time before, for /snapshots/displacement; without it that row is NaN.
  void record_snapshot(const System& sys, const std::vector<double>* reference = nullptr);
  // Writes the buffered records as the next segment file and clears the buffers;
  // does nothing if nothing is buffered.
  void flush_segment();

  int segments() const { return segments_; }
  std::int64_t series_rows() const { return series_rows_; }
  std::int64_t snapshot_count() const { return snapshots_; }
  // On resume (from a checkpoint taken right after a flush): adopt the counts the
  // checkpoint saw. Buffers are dropped; segment files numbered `segments` and
  // above (written after the checkpoint) and unfinished (.tmp) ones are deleted.
  void restore_counts(int segments, std::int64_t series_rows, std::int64_t snapshots);

  // Flushes, then assembles header + segments + final info into out_path, writes
  // the XDMF file beside it (out_path with extension .xdmf), and deletes the
  // segment files. Both files are written under a .tmp name and renamed, the
  // XDMF first, so that out_path appearing means the run file is complete.
  void finish(const System& sys, const RunInfo& info, const std::string& out_path,
              const std::string& stop_reason);

 private:
  // One buffered dataset: records of shape `record` stacked along a new first
  // dimension whose length is the row count of its table.
  using Buffer = std::variant<std::vector<double>*, std::vector<std::int64_t>*,
                              std::vector<std::int32_t>*, std::vector<std::uint8_t>*>;
  struct Column {
    std::string name;                   // dataset path in segment and run file
    std::vector<std::uint64_t> record;  // shape of one record
    Buffer data;
    std::size_t rows;                   // buffered rows of its table
  };
  std::vector<Column> columns();
  std::string segment_path(int k) const;

  std::string work_dir_;
  std::uint64_t n_, nb_, nv_;  // particles, bodies, most core vertices of a body
  int segments_ = 0;
  std::int64_t series_rows_ = 0, snapshots_ = 0;

  struct {
    std::vector<double> time, force, force_mean, torque, torque_mean, vertices, kinetic_energy, max_overlap;
    std::vector<std::int64_t> step, contacts;
    std::array<std::vector<double>, EnergyBalance::kTerms> energy;  // if the ledger is on
  } series_;
  bool energy_ = false;
  struct {
    std::vector<double> time, position, velocity, displacement, omega, theta, vertices;
    std::vector<std::int64_t> step, contact_count;  // contacts per snapshot (segments only)
    std::vector<std::uint8_t> active;
  } snap_;
  struct {
    std::vector<std::int32_t> i, j;
    std::vector<double> fn, ft, overlap, nx, ny, mr, mu_star, line;
    std::vector<std::uint8_t> sliding;
  } contact_;
};

}  // namespace dem2d
