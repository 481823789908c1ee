#include "neighbour/cell_grid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/number_text.hpp"

namespace dem2d {

double CellGrid::cell_count(double xmin, double ymin, double xmax, double ymax, double cell_size) {
  return (std::ceil((xmax - xmin) / cell_size) + 2.0) * (std::ceil((ymax - ymin) / cell_size) + 2.0);
}

void CellGrid::configure(double xmin, double ymin, double xmax, double ymax, double cell_size) {
  if (!(cell_size > 0.0) || !(xmax > xmin) || !(ymax > ymin))
    throw std::invalid_argument("CellGrid: empty domain or non-positive cell size");
  x0_ = xmin - cell_size;
  y0_ = ymin - cell_size;
  inv_cell_ = 1.0 / cell_size;
  const double nx = std::ceil((xmax - xmin) / cell_size) + 2.0;
  const double ny = std::ceil((ymax - ymin) / cell_size) + 2.0;
  if (!(nx * ny <= kMaxCells))
    throw std::invalid_argument("the domain holds more than 2e8 neighbour-search cells of " +
                                sig3(cell_size) + " m; shrink [domain]");
  nx_ = static_cast<int>(nx);
  ny_ = static_cast<int>(ny);
  start_.assign(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
}

int CellGrid::cell_x(double x) const {
  return std::clamp(static_cast<int>((x - x0_) * inv_cell_), 0, nx_ - 1);
}
int CellGrid::cell_y(double y) const {
  return std::clamp(static_cast<int>((y - y0_) * inv_cell_), 0, ny_ - 1);
}

void CellGrid::bin(std::span<const double> x, std::span<const double> y, std::span<const std::uint8_t> active) {
  const std::size_t n = x.size();
  cell_.resize(n);
  std::fill(start_.begin(), start_.end(), 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!active[i]) {
      cell_[i] = -1;
      continue;
    }
    const int c = cell_y(y[i]) * nx_ + cell_x(x[i]);
    cell_[i] = c;
    ++start_[static_cast<std::size_t>(c) + 1];
  }
  for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
  order_.resize(static_cast<std::size_t>(start_.back()));
  fill_.assign(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i)  // ascending i keeps each cell sorted
    if (cell_[i] >= 0) order_[static_cast<std::size_t>(fill_[static_cast<std::size_t>(cell_[i])]++)] =
        static_cast<std::int32_t>(i);
}

}  // namespace dem2d
