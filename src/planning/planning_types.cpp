// Planning's plain types (planning/types.h): the status names, the flight model's
// arithmetic and the options' checks (library uavip_planning_types, which links no
// planner and no collision world).
#include <algorithm>
#include <cmath>

#include "uavip/core/error.h"
#include "uavip/planning/types.h"

namespace uavip::planning {

const char* toString(PathStatus status) {
  switch (status) {
    case PathStatus::Solved:
      return "solved";
    case PathStatus::NoPath:
      return "no_path";
    case PathStatus::Timeout:
      return "timeout";
    case PathStatus::InvalidStart:
      return "invalid_start";
    case PathStatus::InvalidGoal:
      return "invalid_goal";
  }
  return "unknown";
}

const char* toString(SurfaceStatus status) {
  switch (status) {
    case SurfaceStatus::Ok:
      return "ok";
    case SurfaceStatus::Partial:
      return "partial";
    case SurfaceStatus::Blocked:
      return "blocked";
    case SurfaceStatus::NoStops:
      return "no_stops";
    case SurfaceStatus::Failed:
      return "failed";
  }
  return "unknown";
}

const char* toString(StopProblem problem) {
  switch (problem) {
    case StopProblem::None:
      return "none";
    case StopProblem::GimbalLimit:
      return "gimbal_limit";
    case StopProblem::InObstacleSpace:
      return "in_obstacle_space";
    case StopProblem::Unreachable:
      return "unreachable";
  }
  return "unknown";
}

const char* toString(FlightPlan::Status status) {
  switch (status) {
    case FlightPlan::Status::Ok:
      return "ok";
    case FlightPlan::Status::Empty:
      return "empty";
    case FlightPlan::Status::Failed:
      return "failed";
  }
  return "unknown";
}

double FlightModel::segmentSeconds(const Vec3& a, const Vec3& b) const {
  const Vec3 d = b - a;
  const double horizontal = std::hypot(d.x(), d.y()) / cruise_speed_m_s;
  const double vertical = d.z() >= 0.0 ? d.z() / climb_speed_m_s : -d.z() / descent_speed_m_s;
  return std::max(horizontal, vertical);
}

double FlightModel::pathSeconds(const PointList& path) const {
  double t = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) t += segmentSeconds(path[i - 1], path[i]);
  return t;
}

void FlightModel::validate(const std::string& where) const {
  requirePositive(cruise_speed_m_s, where, "cruise_speed_m_s");
  requirePositive(climb_speed_m_s, where, "climb_speed_m_s");
  requirePositive(descent_speed_m_s, where, "descent_speed_m_s");
  require(std::isfinite(hover_s) && hover_s >= 0.0, where, "hover_s must be >= 0 s");
  require(std::isfinite(settle_s) && settle_s >= 0.0, where, "settle_s must be >= 0 s");
  requirePositive(endurance_s, where, "endurance_s");
  require(reserve >= 0.0 && reserve < 1.0, where,
          "reserve must be in [0, 1) (a share of endurance_s)");
}

void MissionOptions::validate(const std::string& where) const {
  requireThat(max_skipped_fraction >= 0.0 && max_skipped_fraction <= 1.0, where,
              "max_skipped_fraction", "in [0, 1]", max_skipped_fraction);
  requireThat(min_coverage >= 0.0 && min_coverage <= 1.0, where, "min_coverage", "in [0, 1]",
              min_coverage);
  requireThat(max_standoff_factor >= 1.0 && max_standoff_factor <= 3.0, where,
              "max_standoff_factor", "in [1, 3] (× the standoff)", max_standoff_factor);
  if (start) require(start->allFinite(), where, "start must be finite");
  requireThat(gimbal.pitch_min_deg <= gimbal.pitch_max_deg, where, "gimbal pitch_min_deg",
              "<= pitch_max_deg", gimbal.pitch_min_deg);
}

void FlightOptions::validate(const std::string& where) const {
  if (home) require(home->allFinite(), where, "home must be finite");
  if (start) require(start->allFinite(), where, "start must be finite");
  model.validate(where);
  requireThat(max_rounds >= 1, where, "max_rounds", ">= 1", max_rounds);
}

}  // namespace uavip::planning
