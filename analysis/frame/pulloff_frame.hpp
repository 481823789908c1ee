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

#include "common/stage_error.hpp"
#include "frame/cell.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

// What a contact's partner is. Grain-grain contacts are `grain`; a contact
// with a body of another role (none in the study's pull-off) is `other`.
enum class Partner : std::uint8_t { grain = 0, left = 1, right = 2, floor = 3, intruder = 4, other = 5 };
const char* partner_name(Partner p);

// The cell's inner faces and, if the run has one, the intruder at one snapshot.
struct PulloffGeometry {
  bool has_intruder() const { return intruder >= 0; }
  int left = -1, right = -1, floor = -1, intruder = -1;  // body indices in the snapshot
  Cell cell;                                             // inner faces (m) and the intruder's outline
  // The intruder, of any shape (its core outline rounded by cap_radius; zeros without one):
  Vec2 centre;                 // mean of its core's vertices (m)
  Vec2 axis{1.0, 0.0};         // unit vector along its core's longest edge, x >= 0 (a sphero-line's direction)
  double core_length = 0.0;    // extent of its core along the axis (a sphero-line's segment length) (m)
  double cap_radius = 0.0;     // half its thickness (m)

  // Intruder centre above the floor's inner face (docs/paper.md: heights from the floor
  // to the intruder's centre; the same as pulloff_metrics).
  double height() const { return centre.y - cell.floor; }
  double length() const { return core_length + 2.0 * cap_radius; }  // tip to tip along the axis (m)
  // Distance from each intruder tip to its wall, (cell width - length) / 2 (m).
  double end_to_wall() const { return 0.5 * (cell.right - cell.left - length()); }
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


// Free-surface height above the floor (m), as bed_metrics measures it
// (columns about one mean diameter wide, mean of the highest grain tops).
double bed_height(const Snapshot& s, const PulloffGeometry& g);

}  // namespace dem2d::analysis
