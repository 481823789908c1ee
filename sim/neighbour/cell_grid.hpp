// Uniform cell grid for O(N) neighbour search. Cells are at least as wide as
// the largest interaction range (d_max + skin), so every partner of a particle
// lies in its own or one of the 8 surrounding cells whatever the size ratio.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace dem2d {

class CellGrid {
 public:
  // At most this many cells (their index is an int; 2e8 cells hold 1.6 GB of offsets).
  static constexpr double kMaxCells = 2.0e8;
  // How many cells configure() makes for this domain and cell size (m).
  static double cell_count(double xmin, double ymin, double xmax, double ymax, double cell_size);

  // Covers [xmin, xmax] x [ymin, ymax] plus one cell of margin on every side;
  // std::invalid_argument beyond kMaxCells (the scene reader refuses such a
  // domain first, naming its keys).
  void configure(double xmin, double ymin, double xmax, double ymax, double cell_size);

  // Counting sort of the active particles into cells: O(N + cells).
  void bin(std::span<const double> x, std::span<const double> y, std::span<const std::uint8_t> active);

  int nx() const { return nx_; }
  int ny() const { return ny_; }
  int cell_x(double x) const;  // clamped to the grid
  int cell_y(double y) const;
  // Particles of cell (cx, cy), ascending index: order()[begin .. end).
  std::int32_t begin(int cx, int cy) const { return start_[static_cast<std::size_t>(cy * nx_ + cx)]; }
  std::int32_t end(int cx, int cy) const { return start_[static_cast<std::size_t>(cy * nx_ + cx + 1)]; }
  const std::vector<std::int32_t>& order() const { return order_; }

 private:
  int nx_ = 0, ny_ = 0;
  double x0_ = 0.0, y0_ = 0.0, inv_cell_ = 0.0;
  std::vector<std::int32_t> start_;  // size cells + 1
  std::vector<std::int32_t> order_;  // particle ids grouped by cell
  std::vector<std::int32_t> cell_;   // cell of each particle (-1 if inactive)
  std::vector<std::int32_t> fill_;   // scratch for the counting sort
};

}  // namespace dem2d
