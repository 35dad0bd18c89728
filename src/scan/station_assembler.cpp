#include "uavip/scan/station_assembler.h"

#include <cmath>
#include <string>

#include "assembler_steps.h"
#include "uavip/core/error.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"

namespace uavip::scan {
namespace {

/// Eq. (1) on every vertical beam (and the horizontal ones with include_horizontal).
void placePoints(const RawLog& log, const Station& st, const ImuTrack& imu,
                 const TranslationTrack& track, bool include_horizontal, StationCloud& out) {
  std::size_t n_beams = 0;
  for (const auto& s : st.vertical) n_beams += s.ranges_m.size();
  out.points.reserve(n_beams);
  const Eigen::Matrix3d mount_r = log.body_T_vertical.linear();
  const Vec3 mount_t = log.body_T_vertical.translation();
  BeamAngles angles;
  for (const LaserScan& s : st.vertical) {
    angles.use(s);
    for (std::size_t i = 0; i < s.ranges_m.size(); ++i) {
      ++out.stats.beams;
      const float r = s.ranges_m[i];
      if (!validRange(r, log.min_range_m, log.max_range_m)) {
        ++out.stats.invalid_beams;
        continue;
      }
      const double t = s.beamTime(i);
      out.points.push_back(imu.at(t) * (mount_r * angles.vertical(r, i) + mount_t) + track.at(t));
    }
  }
  if (!include_horizontal) return;
  for (const LaserScan& s : st.horizontal) {
    angles.use(s);
    for (std::size_t i = 0; i < s.ranges_m.size(); ++i) {
      const float r = s.ranges_m[i];
      if (!validRange(r, log.min_range_m, log.max_range_m)) continue;
      const double t = s.beamTime(i);
      out.points.push_back(imu.at(t) * (log.body_T_horizontal * angles.horizontal(r, i)) +
                           track.at(t));
    }
  }
}

}  // namespace

IcpMethod icpMethodFromString(const std::string& name) {
  if (name == "point_to_line") return IcpMethod::PointToLine2D;
  if (name == "pcl") return IcpMethod::PclPointToPoint;
  throw InputError("scan: icp must be point_to_line or pcl, got '" + name + "'");
}

std::string toString(IcpMethod method) {
  return method == IcpMethod::PointToLine2D ? "point_to_line" : "pcl";
}

void AssemblerOptions::validate(const std::string& where) const {
  table().check(*this, where);
  requirePositive(convergence_m, where, "convergence_m");
  tuning.validate(where + ".tuning");
}

const params::Table<AssemblerOptions>& AssemblerOptions::table() {
  static const params::Table<AssemblerOptions> t = [] {
    using O = AssemblerOptions;
    params::Table<O> p;
    p.add("use_imu_prior", &O::use_imu_prior,
          "rotate horizontal scans by the IMU before ICP (paper)");
    p.add(
         "icp", params::Kind::Text, [](const O& o) { return params::toValue(toString(o.icp)); },
         [](O& o, const params::Value& v) { o.icp = icpMethodFromString(v.text); },
         "horizontal ICP: point_to_line (2D, uavip's) or pcl (PCL's point-to-point)")
        .oneOf({toString(IcpMethod::PointToLine2D), toString(IcpMethod::PclPointToPoint)})
        .storedAt([](const O& o) -> const void* { return &o.icp; });
    p.add("max_iterations", &O::max_iterations, "ICP iterations per scan pair").atLeast(1);
    p.add("max_correspondence_m", &O::max_correspondence_m, "ICP pairs farther apart are ignored")
        .unitIs("m")
        .positive();
    p.add("keyframe_yaw_deg", &O::keyframe_yaw_deg, "new keyframe after this much yaw")
        .unitIs("deg")
        .positive();
    p.add("keyframe_translation_m", &O::keyframe_translation_m, "… or after this much translation")
        .unitIs("m")
        .positive();
    p.add("horizontal_stride", &O::horizontal_stride, "use every n-th horizontal beam in ICP")
        .atLeast(1);
    p.add("imu_smoothing_s", &O::imu_smoothing_s,
          "> 0: local-linear fit of the IMU attitude over this window")
        .unitIs("s")
        .atLeast(0);
    p.add("max_imu_gap_s", &O::max_imu_gap_s, "an IMU gap longer than this is an error")
        .unitIs("s")
        .positive();
    p.add("estimate_z", &O::estimate_z,
          "vertical drift from the vertical scanner's nadir and zenith beams");
    p.add("z_cone_deg", &O::z_cone_deg, "beams within this angle of straight down/up give z")
        .unitIs("deg")
        .above(0)
        .below(90);
    p.add("include_horizontal", &O::include_horizontal,
          "also put the horizontal scanner's points in the cloud (paper: no)");
    p.add("refine_drift", &O::refine_drift, "all beams of the sweep join the drift estimate");
    p.add("drift_segment_deg", &O::drift_segment_deg, "refinement node spacing in yaw")
        .unitIs("deg")
        .above(0)
        .atMost(360);
    p.add("drift_iterations", &O::drift_iterations, "refinement steps").atLeast(1);
    p.add("drift_voxel_m", &O::drift_voxel_m, "refinement voxel and column edge")
        .unitIs("m")
        .positive();
    return p;
  }();
  return t;
}

void AssemblerTuning::validate(const std::string& where) const {
  const auto atLeast = [&](double v, double lo, const char* name) {
    requireThat(std::isfinite(v) && v >= lo, where, name, ">= " + formatNumber(lo), v);
  };
  const auto fraction = [&](double v, const char* name) {
    requireThat(v > 0.0 && v <= 1.0, where, name, "in (0, 1]", v);
  };
  atLeast(line_half_window, 1, "line_half_window");
  requirePositive(line_reach_m, where, "line_reach_m");
  atLeast(line_reach_per_m, 0.0, "line_reach_per_m");
  fraction(line_ratio, "line_ratio");
  requirePositive(huber_m, where, "huber_m");
  requirePositive(tukey_m, where, "tukey_m");
  atLeast(huber_steps, 0, "huber_steps");
  fraction(normal_cos, "normal_cos");
  atLeast(static_cast<double>(min_pairs), 3, "min_pairs");
  atLeast(prior_weight, 0.0, "prior_weight");
  requirePositive(typical_range_m, where, "typical_range_m");
  requireThat(degenerate_fraction >= 0.0 && degenerate_fraction < 1.0, where, "degenerate_fraction",
              "in [0, 1)", degenerate_fraction);
  atLeast(map_spacing_m, 0.0, "map_spacing_m");
  atLeast(min_loop_information, 0.0, "min_loop_information");
  atLeast(static_cast<double>(drift_beam_stride), 1, "drift_beam_stride");
  atLeast(static_cast<double>(drift_horizontal_scan_stride), 1, "drift_horizontal_scan_stride");
  requirePositive(beam_range_sigma_m, where, "beam_range_sigma_m");
  atLeast(beam_angle_sigma_rad, 0.0, "beam_angle_sigma_rad");
  atLeast(odometry_smoothing, 0.0, "odometry_smoothing");
  atLeast(loop_window_deg, 0.0, "loop_window_deg");
  atLeast(max_drift_segments, 1, "max_drift_segments");
  drift.validate(where + ".drift");
}

StationCloud assembleStation(const RawLog& log, std::size_t index,
                             const AssemblerOptions& options) {
  return assembleStation(log, options, stationOdometry(log, index, options));
}

StationCloud assembleStation(const RawLog& log, const AssemblerOptions& options,
                             const StationOdometry& odometry) {
  options.validate();
  if (odometry.index >= log.stations.size()) {
    throw InputError("scan: station index " + std::to_string(odometry.index) + " out of range (" +
                     std::to_string(log.stations.size()) + " stations)");
  }
  const Station& st = log.stations[odometry.index];
  const std::string where = "station " + std::to_string(st.id);
  StationCloud out;
  out.station_id = st.id;
  out.stats = odometry.stats;
  if (odometry.empty) return out;
  const ImuTrack imu(st.imu, options.max_imu_gap_s, options.imu_smoothing_s, where);
  out.loop_closure_m = odometry.loop_closure_m;
  out.loop_closure_information = odometry.loop_closure_information;

  // T: xy from the horizontal odometry, z from the nadir/zenith beams, then (refine_drift)
  // all beams jointly.
  TranslationTrack track = odometryTrack(st, odometry, {});
  auto t_pts = SteadyClock::now();
  track = odometryTrack(st, odometry, verticalDrift(log, st, imu, track, options));
  out.stats.points_s = secondsSince(t_pts);
  if (options.refine_drift) {
    const auto t_refine = SteadyClock::now();
    const DriftRefinement r = refineTrack(log, st, imu, options, track);
    out.stats.refine_s = secondsSince(t_refine);
    out.stats.drift_segments = r.node_times_s.size() > 1 ? r.node_times_s.size() - 1 : 0;
    out.stats.drift_planes = r.planes;
    out.loop_closure_m = r.loop_closure_m;
    out.loop_closure_information = r.loop_closure_information;
  }

  // Poses: R = IMU at the scan start, T = the track at the scan's mid time.
  for (std::size_t k = 0; k < st.horizontal.size(); ++k) {
    const LaserScan& s = st.horizontal[k];
    const double tm = s.t_start_s + 0.5 * s.duration_s;
    out.pose_times_s.push_back(tm);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = imu.at(s.t_start_s).toRotationMatrix();
    pose.translation() = track.at(tm);
    out.poses.push_back(pose);
  }
  t_pts = SteadyClock::now();
  placePoints(log, st, imu, track, options.include_horizontal, out);
  out.stats.points_s += secondsSince(t_pts);
  return out;
}

}  // namespace uavip::scan
