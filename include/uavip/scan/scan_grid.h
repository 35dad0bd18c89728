#pragma once
/// \file
/// Stage 1's nearest-neighbour lookup for 2D scan points (paper §II-A: T from ICP on
/// the horizontal scans): a uniform grid whose cell is the search radius.

#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace uavip::scan {

/// Nearest point within one cell edge of a query, on a grid of that edge. The cells
/// of the points' bounding box are one dense array of offsets into the point
/// indices, cell by cell (a counting sort, so each cell's indices ascend); a box of
/// more than `max_dense_cells` cells (a stray far return) falls back to a hash map
/// of cells. Either way a query reads the 3 × 3 cells around it in the same order,
/// so ties go to the same point. The dense array made stage 1's ICP about 1.8 ×
/// faster than the hash map alone (docs/architecture_notes.md, "Speed"). Holds a
/// reference to the points, which must outlive it unchanged.
class ScanGrid {
 public:
  /// Default bound of the dense array: 4 M cells (16 MB of offsets).
  static constexpr double kMaxDenseCells = 4.0 * 1024 * 1024;

  /// Throws InputError when a coordinate / cell is outside planeCellIndex's range.
  ScanGrid(const std::vector<Eigen::Vector2d>& points, double cell_m,
           double max_dense_cells = kMaxDenseCells);

  /// Index of the nearest point strictly within `cell_m` of q (the first one in
  /// cell order on a tie), or −1.
  int nearest(const Eigen::Vector2d& q) const;

  /// True when the dense array holds the cells (false: the hash map).
  bool dense() const { return !start_.empty(); }

 private:
  std::int64_t cellOf(double v) const;
  std::size_t denseCell(std::int64_t x, std::int64_t y) const {
    return static_cast<std::size_t>((y - y0_) * nx_ + (x - x0_));
  }
  const std::vector<Eigen::Vector2d>& points_;
  double cell_;
  std::int64_t x0_{0}, y0_{0}, nx_{0}, ny_{0};
  std::vector<int> start_;  ///< dense: per cell its first entry in order_ (+ the end)
  std::vector<int> order_;  ///< dense: point indices, cell by cell, ascending in each
  std::unordered_map<std::uint64_t, std::vector<int>> sparse_;  ///< the fallback
};

}  // namespace uavip::scan
