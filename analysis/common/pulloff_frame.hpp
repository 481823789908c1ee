// What the `network` and `friction` stages share about one pull-off snapshot:
// the cell and the intruder (found by their roles in the run file), the intruder's
// height, each contact's partner class and contact point, and binning by
// intruder height. Definitions: analysis/network/README.md ("Shared").
// SI units (m, N/m) throughout.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/study.hpp"
#include "common/stage_error.hpp"
#include "io/run_reader.hpp"

namespace dem2d::analysis {

// What a contact's partner is. Grain-grain contacts are `grain`; a contact
// with a body of another role (none in the study's pull-off) is `other`.
enum class Partner : std::uint8_t { grain = 0, left = 1, right = 2, floor = 3, intruder = 4, other = 5 };
const char* partner_name(Partner p);

// The cell's inner faces and, if the run has one, the intruder at one snapshot.
struct PulloffGeometry {
  bool has_intruder() const { return intruder >= 0; }
  int left = -1, right = -1, floor = -1, intruder = -1;  // body indices in the snapshot
  double x_left = 0.0, x_right = 0.0, y_floor = 0.0;      // inner faces (m)
  // The intruder, of any shape (its core outline rounded by cap_radius; zeros without one):
  Vec2 centre;                 // mean of its core's vertices (m)
  Vec2 axis{1.0, 0.0};         // unit vector along its core's longest edge, x >= 0 (a sphero-line's direction)
  double core_length = 0.0;    // extent of its core along the axis (a sphero-line's segment length) (m)
  double cap_radius = 0.0;     // half its thickness (m)

  // Intruder centre above the floor's inner face (SPEC: heights from the floor
  // to the intruder's centre; the same as pulloff_metrics).
  double height() const { return centre.y - y_floor; }
  double length() const { return core_length + 2.0 * cap_radius; }  // tip to tip along the axis (m)
  // Distance from each intruder tip to its wall, (x_right - x_left - length) / 2 (m).
  double end_to_wall() const { return 0.5 * (x_right - x_left - length()); }
  // Signed position of point p along the intruder's axis from its middle (m).
  double axial(Vec2 p) const;
};

// Throws StageError naming a missing cell body (floor, left_wall, right_wall)
// and listing the snapshot's bodies; a run without an intruder is fine
// (has_intruder() false): the stages then measure what needs no intruder.
PulloffGeometry pulloff_geometry(const Snapshot& s);

// One class per contact of s.contacts.
std::vector<Partner> classify_contacts(const Snapshot& s, const PulloffGeometry& g);

// Where contact c touches: on the line of centres, half the overlap inside
// grain i's surface, x_i - n (r_i - overlap / 2) (n points from the partner to i).
Vec2 contact_point(const Snapshot& s, std::size_t c);

// Mean diameter of the active grains (m); StageError if there are none.
double mean_diameter(const Snapshot& s);

// Free-surface height above the floor (m), as bed_metrics measures it
// (columns about one mean diameter wide, mean of the highest grain tops).
double bed_height(const Snapshot& s, const PulloffGeometry& g);

// Bins of intruder height [k w, (k+1) w), k >= 0, w > 0 (m); heights below 0
// go to bin 0. A height beyond kMaxBins bins (or NaN) is a StageError.
struct HeightBins {
  static constexpr std::size_t kMaxBins = 1000000;
  double width = 0.0;
  std::size_t index(double height) const;
  double lower(std::size_t k) const { return static_cast<double>(k) * width; }
};

// Mean of values by height bin; NaN values are skipped. count[k] = values used in bin k.
struct BinnedMean {
  std::vector<double> mean;
  std::vector<std::int64_t> count;
};
BinnedMean binned_mean(const HeightBins& bins, const std::vector<double>& heights, const std::vector<double>& values);

// The mean of `values` over the entries with lo <= heights < hi, skipping NaN;
// NaN if there are none. `used` (optional) receives the number of entries used.
double mean_in_band(const std::vector<double>& heights, const std::vector<double>& values, double lo, double hi,
                    std::int64_t* used = nullptr);

// Snapshot indices 0, every, 2 every, ... and the last one (every >= 1).
std::vector<std::size_t> every_kth(std::size_t snapshots, std::size_t every);

}  // namespace dem2d::analysis
