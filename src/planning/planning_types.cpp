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
    case StopProblem::MosaicCovered:
      return "mosaic_covered";
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

void FlightModel::validate(const std::string& where) const { table().check(*this, where); }

double sortieSeconds(const Sortie& sortie, const FlightModel& model) {
  return model.pathSeconds(sortie.waypoints) +
         static_cast<double>(sortie.stops.size()) * model.stopSeconds();
}

const params::Table<FlightModel>& FlightModel::table() {
  static const params::Table<FlightModel> t = [] {
    using O = FlightModel;
    params::Table<O> p;
    p.add("cruise_speed_m_s", &O::cruise_speed_m_s, "horizontal speed")
        .unitIs("m/s")
        .positive()
        .fromProfile();
    p.add("climb_speed_m_s", &O::climb_speed_m_s, "vertical speed up")
        .unitIs("m/s")
        .positive()
        .fromProfile();
    p.add("descent_speed_m_s", &O::descent_speed_m_s, "vertical speed down")
        .unitIs("m/s")
        .positive()
        .fromProfile();
    p.add("hover_s", &O::hover_s, "hover per photo").unitIs("s").atLeast(0);
    p.add("settle_s", &O::settle_s, "turn to the stop's yaw and settle the gimbal")
        .unitIs("s")
        .atLeast(0);
    p.add("endurance_s", &O::endurance_s, "battery endurance (one sortie)")
        .unitIs("s")
        .positive()
        .fromProfile();
    p.add("reserve", &O::reserve, "share of endurance_s kept for landing and wind")
        .atLeast(0)
        .below(1);
    return p;
  }();
  return t;
}

void MissionOptions::validate(const std::string& where) const {
  table().check(*this, where);
  requireThat(gimbal.pitch_min_deg <= gimbal.pitch_max_deg, where, "gimbal pitch_min_deg",
              "<= pitch_max_deg", gimbal.pitch_min_deg);
}

const params::Table<MissionOptions>& MissionOptions::table() {
  static const params::Table<MissionOptions> t = [] {
    using O = MissionOptions;
    params::Table<O> p;
    p.add("simplify", &O::simplify, "shortcut the voxel paths (line of sight on the grid)");
    p.add("max_skipped_fraction", &O::max_skipped_fraction,
          "a surface whose unusable stops exceed this share is blocked, else partial")
        .within(0, 1);
    p.add("start", &O::start,
          "take-off / entry point [x, y, z]; must be free (default: the "
          "first stop)")
        .unitIs("m");
    p.add("repair_stops", &O::repair_stops,
          "move a stop inside the obstacle space to a free pose that still sees its centre");
    p.add("min_coverage", &O::min_coverage, "a flyable surface measured below this is partial")
        .within(0, 1);
    p.add("max_standoff_factor", &O::max_standoff_factor,
          "farthest repaired stop, × the standoff (footprint and GSD grow by it)")
        .within(1, 3);
    return p;
  }();
  return t;
}

void FlightOptions::validate(const std::string& where) const {
  if (home) require(home->allFinite(), where, "home must be finite");
  if (start) require(start->allFinite(), where, "start must be finite");
  model.validate(where);
  requireThat(max_rounds >= 1, where, "max_rounds", ">= 1", max_rounds);
}

}  // namespace uavip::planning
