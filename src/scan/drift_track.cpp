// Stage 1's drift refinement step (paper §II-A): the beams as refinement points and
// T(t) refined on them (drift_refinement.h, refineDrift).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "assembler_steps.h"

namespace uavip::scan {
namespace {

/// Position noise of a beam of range ρ: range noise and attitude error [m].
double beamSigma(double range_m, const AssemblerTuning& tuning) {
  const double range_sigma = tuning.beam_range_sigma_m;
  const double angle_sigma = tuning.beam_angle_sigma_rad;
  return std::sqrt(range_sigma * range_sigma + range_m * angle_sigma * range_m * angle_sigma);
}

/// Every vertical beam (every drift_beam_stride-th) and every
/// drift_horizontal_scan_stride-th horizontal scan's beams, as refinement points.
std::vector<DriftPoint> driftPoints(const RawLog& log, const Station& st, const ImuTrack& imu,
                                    const AssemblerTuning& tuning) {
  const std::size_t beam_stride = tuning.drift_beam_stride;
  const std::size_t scan_stride_h = tuning.drift_horizontal_scan_stride;
  std::vector<DriftPoint> pts;
  std::size_t beams = 0;
  for (const auto& s : st.vertical) beams += s.ranges_m.size();
  for (const auto& s : st.horizontal) beams += s.ranges_m.size() / scan_stride_h;
  pts.reserve(beams / beam_stride + 1);
  BeamAngles angles;
  auto add = [&](const std::vector<LaserScan>& scans, const Eigen::Isometry3d& mount,
                 bool horizontal, std::size_t scan_stride) {
    for (std::size_t k = 0; k < scans.size(); k += scan_stride) {
      const LaserScan& s = scans[k];
      angles.use(s);
      for (std::size_t i = k % beam_stride; i < s.ranges_m.size(); i += beam_stride) {
        const float r = s.ranges_m[i];
        if (!validRange(r, log.min_range_m, log.max_range_m)) continue;
        const double t = s.beamTime(i);
        const Vec3 x = horizontal ? angles.horizontal(r, i) : angles.vertical(r, i);
        pts.push_back({imu.at(t) * (mount * x), t, beamSigma(r, tuning), horizontal,
                       static_cast<double>(beam_stride * scan_stride)});
      }
    }
  };
  add(st.vertical, log.body_T_vertical, false, 1);
  add(st.horizontal, log.body_T_horizontal, true, scan_stride_h);
  return pts;
}

/// The track's xy averaged over ±half_s (re-zeroed at the first sample): the
/// odometry's scan-to-scan jitter (a weakly constrained direction jumping at a
/// keyframe) is noise at a time scale the refinement cannot correct.
void smoothTrackXY(TranslationTrack& track, double half_s) {
  const std::size_t n = track.times_s.size();
  if (n < 3 || !(half_s > 0.0)) return;
  std::vector<Vec2> xy(n);
  std::size_t lo = 0, hi = 0;
  Vec2 sum = Vec2::Zero();
  for (std::size_t k = 0; k < n; ++k) {
    while (hi < n && track.times_s[hi] <= track.times_s[k] + half_s)
      sum += track.positions[hi++].head<2>();
    while (track.times_s[lo] < track.times_s[k] - half_s) sum -= track.positions[lo++].head<2>();
    xy[k] = sum / static_cast<double>(hi - lo);
  }
  const Vec2 origin = xy.front();
  for (std::size_t k = 0; k < n; ++k) track.positions[k].head<2>() = xy[k] - origin;
}

}  // namespace

DriftRefinement refineTrack(const RawLog& log, const Station& st, const ImuTrack& imu,
                            const AssemblerOptions& options, TranslationTrack& track) {
  if (track.times_s.size() < 2) return {};
  std::vector<double> yaw(track.times_s.size());
  for (std::size_t k = 0; k < yaw.size(); ++k) yaw[k] = yawOf(imu.at(track.times_s[k]));
  const std::vector<double> swept = sweptYawDeg(yaw);
  const AssemblerTuning& tn = options.tuning;
  const double segment_deg =
      std::max(options.drift_segment_deg, swept.back() / tn.max_drift_segments);
  const std::vector<double> nodes = segmentNodeTimes(track.times_s, swept, segment_deg);
  const double loop_start_s =
      timeAtSweptDeg(track.times_s, swept, swept.back() - tn.loop_window_deg);
  const double segment_s = (nodes.back() - nodes.front()) / static_cast<double>(nodes.size() - 1);
  smoothTrackXY(track, tn.odometry_smoothing * segment_s);
  DriftRefinementOptions o;
  o.iterations = options.drift_iterations;
  o.voxel_m = options.drift_voxel_m;
  o.tuning = tn.drift;
  DriftRefinement r = refineDrift(driftPoints(log, st, imu, tn), track, nodes, loop_start_s, o);
  for (std::size_t k = 0; k < track.times_s.size(); ++k)
    track.positions[k] += r.at(track.times_s[k]);
  return r;
}

}  // namespace uavip::scan
