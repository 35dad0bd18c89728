#include "uavip/scan/scan_grid.h"

#include <algorithm>
#include <limits>

#include "uavip/core/voxel_key.h"

namespace uavip::scan {

ScanGrid::ScanGrid(const std::vector<Eigen::Vector2d>& points, double cell_m,
                   double max_dense_cells)
    : points_(points), cell_(cell_m) {
  if (points_.empty()) return;
  std::int64_t x0 = std::numeric_limits<std::int64_t>::max(), y0 = x0;
  std::int64_t x1 = std::numeric_limits<std::int64_t>::min(), y1 = x1;
  std::vector<std::int64_t> cx(points_.size()), cy(points_.size());
  for (std::size_t i = 0; i < points_.size(); ++i) {
    cx[i] = cellOf(points_[i].x());
    cy[i] = cellOf(points_[i].y());
    x0 = std::min(x0, cx[i]);
    x1 = std::max(x1, cx[i]);
    y0 = std::min(y0, cy[i]);
    y1 = std::max(y1, cy[i]);
  }
  const double cells = (static_cast<double>(x1) - static_cast<double>(x0) + 1.0) *
                       (static_cast<double>(y1) - static_cast<double>(y0) + 1.0);
  if (cells > max_dense_cells) {
    for (std::size_t i = 0; i < points_.size(); ++i)
      sparse_[planeCellKey(cx[i], cy[i])].push_back(static_cast<int>(i));
    return;
  }
  x0_ = x0;
  y0_ = y0;
  nx_ = x1 - x0 + 1;
  ny_ = y1 - y0 + 1;
  start_.assign(static_cast<std::size_t>(nx_ * ny_) + 1, 0);
  for (std::size_t i = 0; i < points_.size(); ++i) ++start_[denseCell(cx[i], cy[i]) + 1];
  for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
  order_.resize(points_.size());
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < points_.size(); ++i)
    order_[static_cast<std::size_t>(fill[denseCell(cx[i], cy[i])]++)] = static_cast<int>(i);
}

std::int64_t ScanGrid::cellOf(double v) const { return planeCellIndex(v, cell_, "scan grid"); }

int ScanGrid::nearest(const Eigen::Vector2d& q) const {
  const std::int64_t cx = cellOf(q.x()), cy = cellOf(q.y());
  double best = cell_ * cell_;
  int best_i = -1;
  const auto visit = [&](const int* first, const int* last) {
    for (const int* it = first; it != last; ++it) {
      const double d2 = (points_[static_cast<std::size_t>(*it)] - q).squaredNorm();
      if (d2 < best) {
        best = d2;
        best_i = *it;
      }
    }
  };
  for (std::int64_t dx = -1; dx <= 1; ++dx) {
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      const std::int64_t x = cx + dx, y = cy + dy;
      if (dense()) {
        if (x < x0_ || x >= x0_ + nx_ || y < y0_ || y >= y0_ + ny_) continue;
        const std::size_t c = denseCell(x, y);
        visit(order_.data() + start_[c], order_.data() + start_[c + 1]);
        continue;
      }
      if (!inPlaneCellRange(x) || !inPlaneCellRange(y)) continue;
      const auto it = sparse_.find(planeCellKey(x, y));
      if (it != sparse_.end()) visit(it->second.data(), it->second.data() + it->second.size());
    }
  }
  return best_i;
}

}  // namespace uavip::scan
