// Stage 1's odometry (paper §II-A): T in xy from ICP of the horizontal scans against a
// keyframe map (with the 2D loop closure), z from the nadir and zenith beams, and the
// track T(t) they give.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "assembler_steps.h"
#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/core/voxel_key.h"

namespace uavip::scan {
namespace {

/// Throws InputError for a scan with a bad time, out of order or outside the IMU's span.
void checkScans(const Station& st, const ImuTrack& imu, double tolerance_s,
                const std::string& where) {
  auto check = [&](const std::vector<LaserScan>& scans, const char* kind) {
    for (std::size_t i = 0; i < scans.size(); ++i) {
      const LaserScan& s = scans[i];
      const double prev_t = i ? scans[i - 1].t_start_s : -std::numeric_limits<double>::infinity();
      if (!std::isfinite(s.t_start_s) || !std::isfinite(s.duration_s) || s.duration_s < 0.0) {
        throw InputError(where + ": " + kind + " scan " + std::to_string(i) +
                         " has a non-finite time");
      }
      if (s.t_start_s < prev_t) {
        throw InputError(where + ": " + kind + " scan " + std::to_string(i) +
                         " starts before the previous one (" + formatNumber(prev_t) + " s -> " +
                         formatNumber(s.t_start_s) + " s)");
      }
      if (s.t_start_s < imu.startTime() - tolerance_s ||
          s.t_start_s + s.duration_s > imu.endTime() + tolerance_s) {
        throw InputError(where + ": " + kind + " scan " + std::to_string(i) + " at " +
                         formatNumber(s.t_start_s) + " s is outside the IMU's time span [" +
                         formatNumber(imu.startTime()) + ", " + formatNumber(imu.endTime()) +
                         "] s");
      }
    }
  };
  check(st.vertical, "vertical");
  check(st.horizontal, "horizontal");
}

/// The horizontal scans as 2D points (IMU-rotated with the prior) with line normals.
std::vector<Scan2D> horizontalScans(const RawLog& log, const Station& st, const ImuTrack& imu,
                                    bool prior, const AssemblerTuning& tuning) {
  std::vector<Scan2D> scans(st.horizontal.size());
  BeamAngles angles;
  for (std::size_t k = 0; k < st.horizontal.size(); ++k) {
    const LaserScan& s = st.horizontal[k];
    angles.use(s);
    scans[k].pts.reserve(s.ranges_m.size());
    for (std::size_t i = 0; i < s.ranges_m.size(); ++i) {
      const float r = s.ranges_m[i];
      if (!validRange(r, log.min_range_m, log.max_range_m)) continue;
      const Vec3 b = log.body_T_horizontal * angles.horizontal(r, i);
      // With the prior: rotate by the IMU at the beam's own time (levels, de-yaws, deskews).
      const Vec3 p = prior ? Vec3(imu.at(s.beamTime(i)) * b) : b;
      scans[k].pts.emplace_back(p.x(), p.y());
    }
    scans[k].normals = makeReference(scans[k], 0.0, Vec2::Zero(), tuning).normals;
  }
  return scans;
}

/// Loop closure of the odometry: the last scan as placed, ICP'd onto the first as
/// placed, in coordinates centred on the last scan's position (so the result is a
/// body offset). Only a closure the scans can see is a measurement: with too few
/// pairs, or a direction no pair fixes (one flat face in view), the offset would read 0.
void odometryLoopClosure(const std::vector<Scan2D>& scans, StationOdometry& odo,
                         const AssemblerOptions& options) {
  if (scans.size() < 2) return;
  const std::size_t last = scans.size() - 1;
  Scan2D first_c;
  for (const auto& p : scans[0].pts)
    first_c.pts.push_back(rot2(odo.theta[0]) * p + odo.trans[0] - odo.trans[last]);
  Reference lref = makeReference(first_c, 0.0, Vec2::Zero(), options.tuning);
  const ScanGrid lgrid(lref.pts, options.max_correspondence_m);
  Scan2D last_c;
  for (const auto& p : scans[last].pts) last_c.pts.push_back(rot2(odo.theta[last]) * p);
  last_c.normals = makeReference(last_c, 0.0, Vec2::Zero(), options.tuning).normals;
  const IcpResult r = icpPointToLine(last_c, lref, lgrid, 0.0, Vec2::Zero(), options, 1);
  odo.loop_closure_information = r.min_information;
  const AssemblerTuning& tn = options.tuning;
  odo.loop_closure_m =
      r.pairs >= tn.min_pairs && r.min_information >= tn.min_loop_information ? r.t.norm() : -1.0;
}

/// T in xy from ICP between horizontal scans and a keyframe map (see the header):
/// per scan, residual yaw θ_k and position t_k in the station frame (station xy =
/// rot(θ_k)·scan_k + t_k), into odo (and its stats). The 2D loop closure only with
/// `loop_closure`: the refinement has its own.
void horizontalOdometry(const RawLog& log, const Station& st, const ImuTrack& imu,
                        const AssemblerOptions& options, bool loop_closure, StationOdometry& odo) {
  const bool prior = options.use_imu_prior;
  const std::vector<Scan2D> scans = horizontalScans(log, st, imu, prior, options.tuning);
  AssemblyStats& stats = odo.stats;
  odo.theta.assign(scans.size(), 0.0);
  odo.trans.assign(scans.size(), Vec2::Zero());
  if (scans.empty()) return;
  double iter_sum = 0.0, rms_sum = 0.0;
  std::size_t icp_runs = 0;
  auto& theta = odo.theta;
  auto& trans = odo.trans;
  // Plain ICP starts from the IMU heading of the first scan (so both modes share the frame).
  theta[0] = prior ? 0.0 : yawOf(imu.at(st.horizontal[0].t_start_s));
  std::size_t kf = 0;
  Reference ref = makeReference(scans[0], theta[0], trans[0], options.tuning);
  auto grid = std::make_unique<ScanGrid>(ref.pts, options.max_correspondence_m);
  stats.keyframes = 1;
  for (std::size_t k = 1; k < scans.size(); ++k) {
    // Guess: the previous pose (the wind is a random walk; plain ICP gets no
    // yaw prediction either: it starts from the last yaw).
    const double th0 = theta[k - 1];
    const Vec2 t0 = trans[k - 1];
    const IcpResult r =
        options.icp == IcpMethod::PointToLine2D
            ? icpPointToLine(scans[k], ref, *grid, th0, t0, options, options.horizontal_stride)
            : icpPcl(scans[k], ref, th0, t0, options, options.horizontal_stride);
    const bool ok = r.converged && r.pairs >= options.tuning.min_pairs && std::isfinite(r.theta) &&
                    r.t.allFinite();
    theta[k] = ok ? r.theta : th0;
    trans[k] = ok ? r.t : t0;
    if (!ok) ++stats.failed_icp;
    iter_sum += r.iterations;
    rms_sum += r.rms;
    ++icp_runs;
    // Yaw since the keyframe: the IMU's (with the prior) or the ICP's own.
    const double yaw_k = prior ? yawOf(imu.at(st.horizontal[k].t_start_s)) + theta[k] : theta[k];
    const double yaw_kf =
        prior ? yawOf(imu.at(st.horizontal[kf].t_start_s)) + theta[kf] : theta[kf];
    if (ok && (std::abs(wrapAngle(yaw_k - yaw_kf)) * 180.0 / kPi > options.keyframe_yaw_deg ||
               (trans[k] - trans[kf]).norm() > options.keyframe_translation_m)) {
      // The reference is a map of all keyframes so far: structure seen earlier in
      // the turn stays matchable (what the scanner sees comes and goes as it yaws).
      // New points join it only where it has none within tuning.map_spacing_m.
      kf = k;
      const Reference add = makeReference(scans[k], theta[k], trans[k], options.tuning);
      for (std::size_t i = 0; i < add.pts.size(); ++i) {
        if (add.normals[i].squaredNorm() == 0.0) continue;
        const int j = grid->nearest(add.pts[i]);
        if (j >= 0 && (ref.pts[static_cast<std::size_t>(j)] - add.pts[i]).norm() <
                          options.tuning.map_spacing_m)
          continue;
        ref.pts.push_back(add.pts[i]);
        ref.normals.push_back(add.normals[i]);
      }
      grid = std::make_unique<ScanGrid>(ref.pts, options.max_correspondence_m);
      ++stats.keyframes;
    }
  }
  if (loop_closure) odometryLoopClosure(scans, odo, options);
  stats.mean_icp_iterations = icp_runs ? iter_sum / static_cast<double>(icp_runs) : 0.0;
  stats.mean_icp_rms_m = icp_runs ? rms_sum / static_cast<double>(icp_runs) : 0.0;
}

/// A 2D height map (cell → mean z of the first points that fell into it).
class HeightMap {
 public:
  explicit HeightMap(double cell) : cell_(cell) {}
  /// z offset of p against the map, or NaN if its cell is empty.
  double offset(const Vec3& p) const {
    const auto it = cells_.find(key(p));
    if (it == cells_.end()) return std::numeric_limits<double>::quiet_NaN();
    return p.z() - it->second.first / it->second.second;
  }
  void add(const Vec3& p) {
    auto& c = cells_[key(p)];
    if (c.second < 8) {  // freeze a cell once it is known, so the map does not drift
      c.first += p.z();
      c.second += 1;
    }
  }

 private:
  std::uint64_t key(const Vec3& p) const {
    return planeCellKey(planeCellIndex(p.x(), cell_, "height map"),
                        planeCellIndex(p.y(), cell_, "height map"));
  }
  double cell_;
  std::unordered_map<std::uint64_t, std::pair<double, int>> cells_;
};

/// Index of the vertical scan starting nearest to time t (scans non-empty).
std::size_t nearestVerticalScan(const std::vector<LaserScan>& vertical, double t) {
  const auto it = std::lower_bound(vertical.begin(), vertical.end(), t,
                                   [](const LaserScan& s, double v) { return s.t_start_s < v; });
  std::size_t j = static_cast<std::size_t>(it - vertical.begin());
  if (j == vertical.size() || (j > 0 && t - vertical[j - 1].t_start_s < vertical[j].t_start_s - t))
    j = j == 0 ? 0 : j - 1;
  return j;
}

}  // namespace

std::vector<double> verticalDrift(const RawLog& log, const Station& st, const ImuTrack& imu,
                                  const TranslationTrack& xy, const AssemblerOptions& options) {
  std::vector<double> z_of_vscan(st.vertical.size(), 0.0);
  if (!options.estimate_z || st.vertical.empty()) return z_of_vscan;
  const double cone = options.z_cone_deg * kPi / 180.0;
  HeightMap below(0.25), above(0.25);
  double z = 0.0;
  std::vector<double> offsets;
  std::vector<std::pair<Vec3, bool>> pts;
  BeamAngles angles;
  const double cos_cone = std::cos(cone);
  for (std::size_t k = 0; k < st.vertical.size(); ++k) {
    const LaserScan& s = st.vertical[k];
    angles.use(s);
    pts.clear();
    offsets.clear();
    for (std::size_t i = 0; i < s.ranges_m.size(); ++i) {
      const float r = s.ranges_m[i];
      if (!validRange(r, log.min_range_m, log.max_range_m)) continue;
      const double t = s.beamTime(i);
      const Eigen::Quaterniond q = imu.at(t);
      const Vec3 dir = q * (log.body_T_vertical.linear() * angles.vertical(1.0, i));
      if (std::abs(dir.z()) < cos_cone) continue;
      Vec3 p = q * (log.body_T_vertical * angles.vertical(r, i)) + xy.at(t);
      p.z() += z;
      const bool down = dir.z() < 0.0;
      const double off = down ? below.offset(p) : above.offset(p);
      if (std::isfinite(off)) offsets.push_back(off);
      pts.emplace_back(p, down);
    }
    double dz = 0.0;
    if (offsets.size() >= 5) dz = upperMedian(offsets);
    z -= dz;
    z_of_vscan[k] = z;
    for (const auto& [p, down] : pts) {
      const Vec3 c(p.x(), p.y(), p.z() - dz);
      if (down) {
        below.add(c);
      } else {
        above.add(c);
      }
    }
  }
  return z_of_vscan;
}

TranslationTrack odometryTrack(const Station& st, const StationOdometry& odo,
                               const std::vector<double>& z_of_vscan) {
  TranslationTrack track;
  if (!st.horizontal.empty()) {
    for (std::size_t k = 0; k < st.horizontal.size(); ++k) {
      const LaserScan& s = st.horizontal[k];
      const double tm = s.t_start_s + 0.5 * s.duration_s;
      const double z = z_of_vscan.empty() ? 0.0 : z_of_vscan[nearestVerticalScan(st.vertical, tm)];
      track.times_s.push_back(tm);
      track.positions.emplace_back(odo.trans[k].x(), odo.trans[k].y(), z);
    }
  } else {
    for (std::size_t k = 0; k < st.vertical.size(); ++k) {
      track.times_s.push_back(st.vertical[k].t_start_s);
      track.positions.emplace_back(0.0, 0.0, z_of_vscan.empty() ? 0.0 : z_of_vscan[k]);
    }
  }
  return track;
}

StationOdometry stationOdometry(const RawLog& log, std::size_t index,
                                const AssemblerOptions& options) {
  options.validate();
  if (index >= log.stations.size()) {
    throw InputError("scan: station index " + std::to_string(index) + " out of range (" +
                     std::to_string(log.stations.size()) + " stations)");
  }
  const Station& st = log.stations[index];
  const std::string where = "station " + std::to_string(st.id);
  StationOdometry out;
  out.index = index;
  out.stats.vertical_scans = st.vertical.size();
  out.stats.horizontal_scans = st.horizontal.size();
  if (st.vertical.empty() && st.horizontal.empty()) {
    out.empty = true;
    return out;
  }
  const ImuTrack imu(st.imu, options.max_imu_gap_s, options.imu_smoothing_s, where);
  checkScans(st, imu, options.max_imu_gap_s, where);
  const auto t_icp = SteadyClock::now();
  horizontalOdometry(log, st, imu, options, !options.refine_drift, out);
  out.stats.icp_s = secondsSince(t_icp);
  return out;
}

}  // namespace uavip::scan
