#pragma once
/// \file
/// Multi-view counts of a plan's photos, what photogrammetry needs beyond "imaged once":
/// for each sample point p_i, the views that image it (coverage_evaluator.h's test:
/// inside the image, range, incidence, GSD, line of sight) and its triangulation angle,
/// the largest angle between two rays from those views' centres c_a, c_b to the point:
///   angle_i = max over a < b of acos(û_a · û_b),  û = (c − p_i) / |c − p_i|,
/// 0 for a point seen once or never. Summaries: the minimum and the median over the
/// points (the median of an even count is the lower middle value).

#include <cstddef>
#include <vector>

#include "uavip/coverage/coverage_evaluator.h"

namespace uavip::coverage {

/// Views per point and triangulation angles of a set of views.
struct MultiViewStats {
  std::size_t points{0};
  std::vector<int> views;         ///< views imaging each point
  std::vector<double> angle_deg;  ///< triangulation angle of each point [deg]
  int views_min{0};               ///< over the points (0 for no point)
  int views_median{0};            ///< lower median over the points
  double angle_min_deg{0.0};      ///< [deg]
  double angle_median_deg{0.0};   ///< lower median [deg]
};

/// The multi-view counts of `points` (normals and two-sided flags as in
/// evaluateCoverage) by `views`. Does not depend on `threads`; throws as
/// imagedByView.
MultiViewStats multiViewStats(const PointList& points, const std::vector<Vec3>& normals,
                              const std::vector<ViewPose>& views, const CameraModel& camera,
                              const CoverageCriteria& criteria, const LineOfSight* los,
                              int threads = 2, const std::vector<char>* two_sided = nullptr);

}  // namespace uavip::coverage
