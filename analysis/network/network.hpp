// The contact force network of one snapshot as a Boost.Graph graph, and what
// the `network` stage measures on it: percolation from the intruder to the
// side walls, the fabric anisotropy of the strong network, keystones (max-flow),
// and the run-level summaries (percolation-loss height, events explained).
// Definitions and reasons: analysis/network/README.md. SI units (m, N/m).
#pragma once

#include <boost/graph/adjacency_list.hpp>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "common/events.hpp"  // RuptureEvent, read_events
#include "frame/height_bins.hpp"
#include "frame/pulloff_frame.hpp"
#include "common/stage_output.hpp"

namespace dem2d::analysis {

// How the floor is kept from linking grains (docs/paper.md: a path through the floor
// does not count). Bodies are never passed through in either rule; with
// bottom_layer_removed the grains touching the floor (fn > 0) are left out too.
enum class FloorRule { vertex_removed, bottom_layer_removed };
const char* floor_rule_name(FloorRule r);
FloorRule floor_rule_from_name(const std::string& name);  // StageError if unknown

// Vertex i (0 <= i < N) is grain i; then the left wall, right wall, floor and
// intruder. One edge per contact with fn > 0, weight fn (N/m): the network of
// compressive forces, whose edges are the capacities of the max-flow and the
// paths of percolation. With cohesion, tensile contacts (fn < 0, touching or
// across a gap) are not edges and do not enter the mean: a pull cannot carry
// the load a compressive chain carries to the walls. Contacts with other
// bodies (none in the study) are left out.
struct ContactGraph {
  using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS, boost::no_property,
                                      boost::property<boost::edge_weight_t, double>>;
  Graph graph;
  std::size_t grains = 0;
  double mean_fn = 0.0;  // mean fn over the edges (0 without edges)

  std::size_t left() const { return grains; }
  std::size_t right() const { return grains + 1; }
  std::size_t floor() const { return grains + 2; }
  std::size_t intruder() const { return grains + 3; }
  std::size_t edges() const { return boost::num_edges(graph); }
  std::int64_t edges_above(double fn) const;  // edges with weight > fn (the strong network's size)
};
ContactGraph build_contact_graph(const Snapshot& s, const std::vector<Partner>& partners);

// Whether `source` (a body's vertex: the intruder, or the left wall for a
// wall-to-wall span) is connected to each side wall through contacts with
// fn > threshold whose every intermediate vertex is a grain (bodies are path
// ends only) and, with bottom_layer_removed, not a grain touching the floor.
struct Percolation {
  bool left = false, right = false;
  bool both() const { return left && right; }
  bool either() const { return left || right; }
};
Percolation percolation(const ContactGraph& g, double threshold, FloorRule rule, std::size_t source);

// Fabric tensor F = <n n> of a set of unit normals; anisotropy
// 2 (l1 - l2) / (l1 + l2) (0 isotropic, 2 all parallel), angle of the major
// axis from +x in degrees [0, 180) (90 = vertical). NaN when fewer than
// min_contacts. noise = sqrt(pi / n): the mean anisotropy of n isotropic
// random directions (the level below which anisotropy is not resolved);
// debiased = sqrt(max(0, a^2 - 4/n)) removes that finite-n bias from a^2
// (E[a^2] = 4/n for isotropic directions).
struct Fabric {
  double anisotropy = std::numeric_limits<double>::quiet_NaN();
  double debiased = std::numeric_limits<double>::quiet_NaN();
  double angle_deg = std::numeric_limits<double>::quiet_NaN();
  double noise = std::numeric_limits<double>::quiet_NaN();
  std::int64_t contacts = 0;
};
Fabric fabric(const std::vector<Vec2>& normals, std::size_t min_contacts);

// The fabric of the grain-grain contacts with fn > threshold whose contact
// point lies in y_min <= y < y_max (the cell's full width).
Fabric region_fabric(const Snapshot& s, const std::vector<Partner>& partners, double threshold, double y_min,
                     double y_max, std::size_t min_contacts);

// Keystones: max-flow from the intruder to each side wall through the
// strong network (fn > threshold, same paths as percolation), capacities fn.
// A candidate is a grain touching an intruder end by a strong contact (its
// centre within end_zone of a segment end along the axis, or beyond it);
// share_w = (flow_w - flow_w without the grain) / flow_w (0 when flow_w = 0).
struct KeystoneCandidate {
  std::int32_t grain = -1;
  int end = 0;  // -1: end a of the segment, +1: end b
  double share_left = 0.0, share_right = 0.0;
  double share() const { return share_left > share_right ? share_left : share_right; }
};
struct KeystoneAnalysis {
  double flow_left = 0.0, flow_right = 0.0;  // max flow (N/m)
  std::vector<KeystoneCandidate> candidates;
  // Grains whose share for either wall is >= min_share, ascending.
  std::vector<std::int32_t> keystones(double min_share) const;
};
KeystoneAnalysis analyse_keystones(const ContactGraph& g, const Snapshot& s, const PulloffGeometry& geo,
                                   double threshold, FloorRule rule, double end_zone);

// The force-network figure data of some snapshots: one segment per contact
// with fn > 0 (not with `other` bodies), from grain i's centre to the partner
// grain's centre or to the body's surface along the normal.
struct ForceSegments {
  std::vector<std::int64_t> snapshot, start = {0};
  std::vector<double> x0, y0, x1, y1, fn;
  std::vector<std::uint8_t> partner, strong;
  // Appends snapshot s's contacts; strong: fn > this (N/m).
  void add(const Snapshot& s, const std::vector<Partner>& partners, double strong_fn);
  // Appends another collection's snapshots after these.
  void append(const ForceSegments& o);
  void write(H5Output& h) const;  // figure/...
};

// Percolating fraction of snapshots per height bin, and the percolation-loss
// height: the upper edge of the highest bin whose fraction is >= level (above
// it every bin stays below); the lower edge of the lowest bin if none reaches
// it; nullopt if the highest bin does (never lost).
struct PercolationProfile {
  std::vector<double> lower;  // bin lower edges (m), bins with snapshots only
  std::vector<double> upper;
  std::vector<std::int64_t> snapshots;
  std::vector<double> fraction;
};
PercolationProfile percolation_profile(const HeightBins& bins, const std::vector<double>& heights,
                                       const std::vector<std::uint8_t>& flags);
std::optional<double> loss_height(const PercolationProfile& p, double level);

// The fraction of snapshots with lo <= height < hi whose flag is set (NaN if none).
double flagged_fraction(const std::vector<double>& heights, const std::vector<std::uint8_t>& flags, double lo,
                        double hi, std::int64_t* used = nullptr);


// The snapshots bracketing a drop: `before` the last at or before peak_time,
// `after` the first at or after drop_end_time; resolved when both exist and
// each is within max_gap (s) of its event time.
struct EventWindow {
  std::int64_t before = -1, after = -1;
  bool resolved = false;
};
EventWindow event_window(const std::vector<double>& times, const RuptureEvent& e, double max_gap);

// The largest displacement between two snapshots among `grains`, in units of
// each grain's own diameter; grain = -1 and 0 when the set is empty.
struct Displacement {
  std::int32_t grain = -1;
  double over_d = 0.0;
  double dx = 0.0, dy = 0.0;  // of that grain (m)
};
Displacement largest_displacement(const std::vector<std::int32_t>& grains, const std::vector<Vec2>& from,
                                  const std::vector<Vec2>& to, const std::vector<double>& diameter);

}  // namespace dem2d::analysis
