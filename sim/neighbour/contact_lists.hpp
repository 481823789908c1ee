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
// at each rebuild and is zeroed by the kernel as soon as a contact opens; so
// are the results of the last force evaluation and the energy ledger's springs
// at the start of the step (`carried()`), so that a rebuild changes nothing
// any reader of the lists sees.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "shape/shape.hpp"
#include "core/aligned_vector.hpp"
#include "core/state.hpp"
#include "neighbour/cell_grid.hpp"

namespace dem2d {

struct PairList {
  AlignedVector<std::int32_t> start;    // N + 1
  AlignedVector<std::int32_t> owner;    // i of each slot (the row it belongs to)
  AlignedVector<std::int32_t> partner;  // j > i, ascending within a row
  // constants of the pair, set at rebuild (contiguous loads in the kernel)
  AlignedVector<double> ri, rj;       // radii (m)
  AlignedVector<double> sqrt_meff;    // sqrt(m_i m_j / (m_i + m_j)) (sqrt(kg/m))
  AlignedVector<double> sqrt_ieff;    // sqrt(I_i I_j / (I_i + I_j)) (sqrt(kg m))
  // history
  AlignedVector<double> ft;  // tangential spring (N/m) along t = z x n
  AlignedVector<double> mr;  // rolling spring: moment on i (N)
  // last evaluation (zero for candidates that do not touch)
  AlignedVector<double> fx, fy;  // force on i (N/m); j receives the opposite
  AlignedVector<double> ti, tj;  // torque on i and on j (N)
  AlignedVector<double> fn;      // normal force (N/m)
  AlignedVector<double> overlap; // -delta (m), positive when touching
  // the springs at the start of the step (energy ledger only)
  AlignedVector<double> ft_prev, mr_prev;
  // reverse index: for particle k, the slots whose partner is k (ascending i)
  AlignedVector<std::int32_t> rev_start, rev_slot;

  std::size_t slots() const { return partner.size(); }
  void resize_slots(std::size_t n);  // sizes the per-slot arrays to n, zeroed

  // The per-slot arrays a rebuild and a checkpoint carry over, by name.
  static constexpr std::array<std::pair<const char*, AlignedVector<double> PairList::*>, 10> carried() {
    return {{{"ft", &PairList::ft}, {"mr", &PairList::mr}, {"fx", &PairList::fx}, {"fy", &PairList::fy},
             {"ti", &PairList::ti}, {"tj", &PairList::tj}, {"fn", &PairList::fn},
             {"overlap", &PairList::overlap}, {"ft_prev", &PairList::ft_prev}, {"mr_prev", &PairList::mr_prev}}};
  }
};

struct WallList {
  AlignedVector<std::int32_t> start;  // N + 1
  AlignedVector<std::int32_t> owner;  // the grain of each slot
  AlignedVector<std::int32_t> body;   // ascending within a row
  AlignedVector<double> sqrt_m;       // sqrt(m_i) (sqrt(kg/m)), set at rebuild: a body's mass is infinite
  AlignedVector<double> sqrt_i;       // sqrt(I_i) (sqrt(kg m)), likewise
  // history
  AlignedVector<double> ft, mr;
  // last evaluation
  AlignedVector<double> fx, fy;      // force on the grain (N/m); the body receives the opposite
  AlignedVector<double> tq;          // torque on the grain (N)
  AlignedVector<double> cx, cy;      // contact point (m), for the torque on the body
  AlignedVector<double> fn, overlap;
  // the springs at the start of the step (energy ledger only)
  AlignedVector<double> ft_prev, mr_prev;
  // this step's closest point of the body, with polygon bodies only (the
  // kernel's narrow phase): signed distance (m) and normal to the grain
  AlignedVector<double> dist, nx, ny;

  std::size_t slots() const { return body.size(); }
  void resize_slots(std::size_t n);  // sizes the per-slot arrays to n, zeroed

  // The per-slot arrays a rebuild and a checkpoint carry over, by name.
  static constexpr std::array<std::pair<const char*, AlignedVector<double> WallList::*>, 11> carried() {
    return {{{"ft", &WallList::ft}, {"mr", &WallList::mr}, {"fx", &WallList::fx}, {"fy", &WallList::fy},
             {"tq", &WallList::tq}, {"cx", &WallList::cx}, {"cy", &WallList::cy}, {"fn", &WallList::fn},
             {"overlap", &WallList::overlap}, {"ft_prev", &WallList::ft_prev}, {"mr_prev", &WallList::mr_prev}}};
  }
};

class NeighbourLists {
 public:
  // domain: region the grid covers; r_max: largest grain radius; skin (m);
  // range: how far beyond touching a contact acts (m; cohesion), so that a
  // candidate is any pair within range + skin of touching.
  void configure(double xmin, double ymin, double xmax, double ymax, double r_max, double skin,
                 double range = 0.0);
  // The grid's cell width for these (m): a candidate pair is within one cell.
  static double cell_width(double r_max, double skin, double range) { return 2.0 * r_max + skin + range; }
  double r_max() const { return r_max_; }  // the largest grain radius the lists were configured for (m)
  double skin() const { return skin_; }

  void rebuild_pairs(const Particles& p);
  // Uses the grid binned by the last rebuild_pairs: call it after that.
  void rebuild_walls(const Particles& p, const std::vector<Shape>& shape,
                     const std::vector<double>& body_radius, const std::vector<std::uint8_t>& body_active);

  // The slot of the candidate contact (i, partner j) / (i, body b), or -1 if
  // the lists hold no such candidate.
  std::int64_t pair_slot(std::int32_t i, std::int32_t j) const;
  std::int64_t wall_slot(std::int32_t i, std::int32_t b) const;
  // Sets the stored history of a candidate contact; false if there is none.
  bool set_pair_history(std::int32_t i, std::int32_t j, double ft, double mr);
  bool set_wall_history(std::int32_t i, std::int32_t b, double ft, double mr);

  PairList pairs;
  WallList walls;
  std::int64_t rebuild_count = 0;

 private:
  CellGrid grid_;
  double skin_ = 0.0, reach_ = 0.0, r_max_ = 0.0;  // reach_: skin + range
  PairList old_pairs_;
  WallList old_walls_;
  std::vector<std::int32_t> row_;  // scratch
  std::vector<std::pair<std::int32_t, std::int32_t>> wall_candidates_;  // scratch: (grain, body)
};

}  // namespace dem2d
