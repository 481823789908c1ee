// Verlet lists with a skin: the candidate contacts of every particle, stored
// as compressed rows (row i = slots [start[i], start[i+1])), plus per-slot
// contact history and the results of the last force evaluation.
//
// Pairs are a half list (partner j > i, ascending in each row) with a reverse
// index, so that each pair is evaluated once and each particle then sums its
// contacts in a fixed order. That order does not depend on the thread count or
// on when the list was last rebuilt, which makes runs bitwise reproducible and
// restarts bitwise identical.
//
// History (tangential spring, rolling moment) is carried over to the new list
// at each rebuild and is zeroed by the kernel as soon as a contact opens.
#pragma once

#include <cstdint>
#include <vector>

#include "contact/spheroline.hpp"
#include "core/state.hpp"
#include "neighbour/cell_grid.hpp"

namespace dem2d {

struct PairList {
  std::vector<std::int32_t> start;    // N + 1
  std::vector<std::int32_t> owner;    // i of each slot (the row it belongs to)
  std::vector<std::int32_t> partner;  // j > i, ascending within a row
  // constants of the pair, set at rebuild (contiguous loads in the kernel)
  std::vector<double> ri, rj;       // radii (m)
  std::vector<double> sqrt_meff;    // sqrt(m_i m_j / (m_i + m_j)) (sqrt(kg/m))
  // history
  std::vector<double> ft;  // tangential spring (N/m) along t = z x n
  std::vector<double> mr;  // rolling moment on i (N)
  // last evaluation (zero for candidates that do not touch)
  std::vector<double> fx, fy;  // force on i (N/m); j receives the opposite
  std::vector<double> ti, tj;  // torque on i and on j (N)
  std::vector<double> fn;      // normal force (N/m)
  std::vector<double> overlap; // -delta (m), positive when touching
  // reverse index: for particle k, the slots whose partner is k (ascending i)
  std::vector<std::int32_t> rev_start, rev_slot;

  std::size_t slots() const { return partner.size(); }
  void resize_slots(std::size_t n);  // sizes the per-slot arrays to n, zeroed
};

struct WallList {
  std::vector<std::int32_t> start;  // N + 1
  std::vector<std::int32_t> owner;  // the grain of each slot
  std::vector<std::int32_t> body;   // ascending within a row
  // history
  std::vector<double> ft, mr;
  // last evaluation
  std::vector<double> fx, fy;      // force on the grain (N/m); the body receives the opposite
  std::vector<double> tq;          // torque on the grain (N)
  std::vector<double> cx, cy;      // contact point (m), for the torque on the body
  std::vector<double> fn, overlap;

  std::size_t slots() const { return body.size(); }
  void resize_slots(std::size_t n);  // sizes the per-slot arrays to n, zeroed
};

class NeighbourLists {
 public:
  // domain: region the grid covers; r_max: largest grain radius; skin (m).
  void configure(double xmin, double ymin, double xmax, double ymax, double r_max, double skin);
  double skin() const { return skin_; }

  void rebuild_pairs(const Particles& p);
  void rebuild_walls(const Particles& p, const std::vector<Segment>& seg,
                     const std::vector<double>& seg_radius, const std::vector<std::uint8_t>& seg_active);

  // Sets the stored history of the candidate contact (i, partner j) / (i, body
  // b); false if the lists hold no such candidate.
  bool set_pair_history(std::int32_t i, std::int32_t j, double ft, double mr);
  bool set_wall_history(std::int32_t i, std::int32_t b, double ft, double mr);

  PairList pairs;
  WallList walls;
  std::int64_t rebuild_count = 0;

 private:
  CellGrid grid_;
  double skin_ = 0.0;
  PairList old_pairs_;
  WallList old_walls_;
  std::vector<std::int32_t> row_;  // scratch
};

}  // namespace dem2d
