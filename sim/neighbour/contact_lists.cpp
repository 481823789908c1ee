#include "neighbour/contact_lists.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace dem2d {

namespace {

// Copies the carried arrays (history, last evaluation) of every contact
// present in both lists. Rows of both lists are sorted by `key`, so this is
// one merge per row.
template <class List>
void carry_history(List& nl, const List& ol, AlignedVector<std::int32_t> List::*key) {
  const auto& nk = nl.*key;
  const auto& ok = ol.*key;
  for (std::size_t i = 0; i + 1 < nl.start.size(); ++i) {
    auto s = static_cast<std::size_t>(nl.start[i]), o = static_cast<std::size_t>(ol.start[i]);
    const auto s_end = static_cast<std::size_t>(nl.start[i + 1]);
    const auto o_end = static_cast<std::size_t>(ol.start[i + 1]);
    while (s < s_end && o < o_end) {
      if (nk[s] < ok[o]) {
        ++s;
      } else if (ok[o] < nk[s]) {
        ++o;
      } else {
        for (const auto& [name, a] : List::carried()) (nl.*a)[s] = (ol.*a)[o];
        ++s;
        ++o;
      }
    }
  }
}

}  // namespace

void PairList::resize_slots(std::size_t n) {
  for (auto* v : {&ri, &rj, &sqrt_meff, &sqrt_ieff}) v->assign(n, 0.0);
  for (const auto& [name, a] : carried()) (this->*a).assign(n, 0.0);
}

void WallList::resize_slots(std::size_t n) {
  for (auto* v : {&sqrt_m, &sqrt_i, &dist, &nx, &ny}) v->assign(n, 0.0);
  for (const auto& [name, a] : carried()) (this->*a).assign(n, 0.0);
}

void NeighbourLists::configure(double xmin, double ymin, double xmax, double ymax, double r_max,
                               double skin, double range) {
  skin_ = skin;
  reach_ = skin + range;
  r_max_ = r_max;
  grid_.configure(xmin, ymin, xmax, ymax, cell_width(r_max, skin, range));
}

void NeighbourLists::rebuild_pairs(const Particles& p) {
  const std::size_t n = p.size();
  std::swap(pairs, old_pairs_);
  PairList& nl = pairs;
  const PairList& ol = old_pairs_;
  const bool have_old = ol.start.size() == n + 1;

  grid_.bin(p.x, p.y, p.active);
  const auto& order = grid_.order();

  nl.start.assign(n + 1, 0);
  nl.partner.clear();
  for (std::size_t i = 0; i < n; ++i) {
    nl.start[i] = static_cast<std::int32_t>(nl.partner.size());
    if (!p.active[i]) continue;
    const double xi = p.x[i], yi = p.y[i], ri = p.radius[i] + reach_;
    const int cx = grid_.cell_x(xi), cy = grid_.cell_y(yi);
    row_.clear();
    for (int gy = std::max(cy - 1, 0); gy <= std::min(cy + 1, grid_.ny() - 1); ++gy)
      for (int gx = std::max(cx - 1, 0); gx <= std::min(cx + 1, grid_.nx() - 1); ++gx)
        for (std::int32_t k = grid_.begin(gx, gy); k < grid_.end(gx, gy); ++k) {
          const auto j = static_cast<std::size_t>(order[static_cast<std::size_t>(k)]);
          if (j <= i) continue;
          const double dx = xi - p.x[j], dy = yi - p.y[j], reach = ri + p.radius[j];
          if (dx * dx + dy * dy < reach * reach) row_.push_back(static_cast<std::int32_t>(j));
        }
    std::sort(row_.begin(), row_.end());
    nl.partner.insert(nl.partner.end(), row_.begin(), row_.end());
  }
  nl.start[n] = static_cast<std::int32_t>(nl.partner.size());
  nl.resize_slots(nl.partner.size());
  nl.owner.resize(nl.partner.size());
  for (std::size_t i = 0; i < n; ++i)
    for (auto s = static_cast<std::size_t>(nl.start[i]); s < static_cast<std::size_t>(nl.start[i + 1]); ++s) {
      const auto j = static_cast<std::size_t>(nl.partner[s]);
      nl.owner[s] = static_cast<std::int32_t>(i);
      nl.ri[s] = p.radius[i];
      nl.rj[s] = p.radius[j];
      nl.sqrt_meff[s] = 1.0 / std::sqrt(p.inv_mass[i] + p.inv_mass[j]);
      nl.sqrt_ieff[s] = 1.0 / std::sqrt(p.inv_inertia[i] + p.inv_inertia[j]);
    }

  if (have_old) carry_history(nl, ol, &PairList::partner);

  // reverse index, filled in slot order so each particle's entries ascend in i
  nl.rev_start.assign(n + 1, 0);
  for (const std::int32_t j : nl.partner) ++nl.rev_start[static_cast<std::size_t>(j) + 1];
  for (std::size_t k = 1; k <= n; ++k) nl.rev_start[k] += nl.rev_start[k - 1];
  nl.rev_slot.resize(nl.partner.size());
  row_.assign(nl.rev_start.begin(), nl.rev_start.end() - 1);
  for (std::size_t s = 0; s < nl.partner.size(); ++s)
    nl.rev_slot[static_cast<std::size_t>(row_[static_cast<std::size_t>(nl.partner[s])]++)] =
        static_cast<std::int32_t>(s);
  ++rebuild_count;
}

void NeighbourLists::rebuild_walls(const Particles& p, const std::vector<Shape>& shape,
                                   const std::vector<double>& body_radius,
                                   const std::vector<std::uint8_t>& body_active) {
  const std::size_t n = p.size();
  std::swap(walls, old_walls_);
  WallList& nl = walls;
  const WallList& ol = old_walls_;
  const bool have_old = ol.start.size() == n + 1;

  // candidates from the grid cells within reach of each body (the grid was
  // binned by rebuild_pairs), then in rows: ascending grain, ascending body
  wall_candidates_.clear();
  for (std::size_t b = 0; b < shape.size(); ++b) {
    if (!body_active[b]) continue;
    const Shape& g = shape[b];
    const Bounds box = core_bounds(g);
    const double reach = body_radius[b] + r_max_ + reach_;
    const int cx0 = grid_.cell_x(box.xmin - reach), cx1 = grid_.cell_x(box.xmax + reach);
    const int cy0 = grid_.cell_y(box.ymin - reach), cy1 = grid_.cell_y(box.ymax + reach);
    for (int cy = cy0; cy <= cy1; ++cy)
      for (int cx = cx0; cx <= cx1; ++cx)
        for (std::int32_t k = grid_.begin(cx, cy); k < grid_.end(cx, cy); ++k) {
          const auto i = static_cast<std::size_t>(grid_.order()[static_cast<std::size_t>(k)]);
          if (closest_point(g, p.x[i], p.y[i]).dist < p.radius[i] + body_radius[b] + reach_)
            wall_candidates_.emplace_back(static_cast<std::int32_t>(i), static_cast<std::int32_t>(b));
        }
  }
  std::sort(wall_candidates_.begin(), wall_candidates_.end());
  nl.start.assign(n + 1, 0);
  nl.owner.clear();
  nl.body.clear();
  for (const auto& [i, b] : wall_candidates_) {
    ++nl.start[static_cast<std::size_t>(i) + 1];
    nl.owner.push_back(i);
    nl.body.push_back(b);
  }
  for (std::size_t i = 1; i <= n; ++i) nl.start[i] += nl.start[i - 1];
  nl.resize_slots(nl.body.size());
  for (std::size_t s = 0; s < nl.slots(); ++s) {
    const auto i = static_cast<std::size_t>(nl.owner[s]);
    nl.sqrt_m[s] = std::sqrt(p.mass[i]);
    nl.sqrt_i[s] = 1.0 / std::sqrt(p.inv_inertia[i]);
  }

  if (have_old) carry_history(nl, ol, &WallList::body);
}

namespace {
template <class List>
std::int64_t find_slot(const List& L, const AlignedVector<std::int32_t>& key, std::int32_t i, std::int32_t k) {
  const auto row = static_cast<std::size_t>(i);
  if (i < 0 || row + 1 >= L.start.size()) return -1;
  const auto first = key.begin() + L.start[row], last = key.begin() + L.start[row + 1];
  const auto it = std::lower_bound(first, last, k);  // rows are sorted by key
  if (it == last || *it != k) return -1;
  return it - key.begin();
}

template <class List>
bool set_history(List& L, std::int64_t slot, double ft, double mr) {
  if (slot < 0) return false;
  L.ft[static_cast<std::size_t>(slot)] = ft;
  L.mr[static_cast<std::size_t>(slot)] = mr;
  return true;
}
}  // namespace

std::int64_t NeighbourLists::pair_slot(std::int32_t i, std::int32_t j) const {
  return find_slot(pairs, pairs.partner, i, j);
}

std::int64_t NeighbourLists::wall_slot(std::int32_t i, std::int32_t b) const {
  return find_slot(walls, walls.body, i, b);
}

bool NeighbourLists::set_pair_history(std::int32_t i, std::int32_t j, double ft, double mr) {
  return set_history(pairs, pair_slot(i, j), ft, mr);
}

bool NeighbourLists::set_wall_history(std::int32_t i, std::int32_t b, double ft, double mr) {
  return set_history(walls, wall_slot(i, b), ft, mr);
}

}  // namespace dem2d
