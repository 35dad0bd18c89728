#pragma once
/// \file
/// A surface's boundary and photo stops scored against the simulator's ground truth
/// (paper §II-D boundaries, §II-F stops, §III-B "extra areas should be
/// accounted for" on concave surfaces). Evaluation, not a stage: the concave-wall
/// test and `uavip_boundary_bench` call it with the true rectangles of one plane.

#include <cstddef>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/coverage/flight_strategy.h"
#include "uavip/sim/world_model.h"

namespace uavip::app {

/// How well one surface's boundary and stops match the true rectangles of its plane.
struct BoundaryScore {
  std::size_t stops{0};           ///< photo stops of the strategy
  std::size_t stops_over_air{0};  ///< stops whose view ray (position → target) hits no rectangle
  double coverage{0.0};           ///< share of the true wall's samples inside some stop's footprint
  double area_m2{0.0};            ///< the surface's area (boundary minus holes) [m²]
  double truth_area_m2{0.0};      ///< sum of the rectangles' areas (they must not overlap) [m²]
  double area_error{0.0};         ///< |area − truth| / truth
};

/// Scores `strategy`'s stops over `surface` against `truth` (rectangles of one plane):
/// a stop is over air when the ray from its position through its target meets no
/// rectangle (exact ray–rectangle test, no tolerance); coverage samples every
/// rectangle on a lattice of `sample_m` and counts a sample covered when it lies in
/// some stop's footprint (|d·axis_w| ≤ w/2, |d·axis_h| ≤ h/2, d from the target).
/// Brute force: O(samples × stops).
BoundaryScore scoreBoundary(const Surface& surface, const coverage::FlightStrategy& strategy,
                            const std::vector<sim::Rect>& truth, double sample_m = 0.02);

}  // namespace uavip::app
