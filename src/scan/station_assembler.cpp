// GCC 12 reports false positives (-Warray-bounds, -Wmaybe-uninitialized) inside the
// Eigen/SSE code that PCL's registration templates instantiate here (set before any
// include: the warnings are attributed to the Eigen headers).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Warray-bounds"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "uavip/scan/station_assembler.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/transformation_estimation_2D.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <unordered_map>

#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/core/voxel_key.h"
#include "uavip/scan/drift_refinement.h"
#include "uavip/scan/scan_grid.h"

namespace uavip::scan {
namespace {

using Vec2 = Eigen::Vector2d;

Eigen::Matrix2d rot2(double theta) {
  Eigen::Matrix2d r;
  const double c = std::cos(theta), s = std::sin(theta);
  r << c, -s, s, c;
  return r;
}

using Grid2D = ScanGrid;

/// cos α and sin α of every beam of a scan, α = angle_min + i·step (eq. (1)), taken
/// once per scan geometry and kept while the next scans share it (each scanner's
/// do): the same values std::cos and std::sin give for that α, so the beams are the
/// verticalBeam / horizontalBeam ones bit for bit, without two trig calls per beam.
class BeamAngles {
 public:
  /// Makes the table fit `s` (recomputed only when its geometry differs).
  void use(const LaserScan& s) {
    if (s.angle_min_rad == angle_min_ && s.angle_step_rad == angle_step_ &&
        s.ranges_m.size() <= cos_.size())
      return;
    angle_min_ = s.angle_min_rad;
    angle_step_ = s.angle_step_rad;
    cos_.resize(s.ranges_m.size());
    sin_.resize(s.ranges_m.size());
    for (std::size_t i = 0; i < cos_.size(); ++i) {
      const double a = angle_min_ + static_cast<double>(i) * angle_step_;
      cos_[i] = std::cos(a);
      sin_[i] = std::sin(a);
    }
  }
  /// verticalBeam(r, α_i).
  Vec3 vertical(double r, std::size_t i) const { return verticalBeam(r, cos_[i], sin_[i]); }
  /// horizontalBeam(r, α_i).
  Vec3 horizontal(double r, std::size_t i) const { return horizontalBeam(r, cos_[i], sin_[i]); }

 private:
  double angle_min_{std::numeric_limits<double>::quiet_NaN()};  // no table yet
  double angle_step_{std::numeric_limits<double>::quiet_NaN()};
  std::vector<double> cos_, sin_;
};

/// A horizontal scan as 2D points (in beam order) in some frame, with the line
/// normals there (zero where the neighbourhood is not a line).
struct Scan2D {
  std::vector<Vec2> pts;
  std::vector<Vec2> normals;
};

/// A keyframe: points in the station frame with line normals (zero where unknown).
struct Reference {
  std::vector<Vec2> pts;
  std::vector<Vec2> normals;
};

/// A scan placed by (theta, t), with the line normal of each point (AssemblerTuning's
/// line fit; zero where the neighbourhood is not a line).
Reference makeReference(const Scan2D& scan, double theta, const Vec2& t,
                        const AssemblerTuning& tuning) {
  const int half = tuning.line_half_window;
  Reference ref;
  const Eigen::Matrix2d r = rot2(theta);
  ref.pts.reserve(scan.pts.size());
  for (const auto& p : scan.pts) ref.pts.push_back(r * p + t);
  ref.normals.assign(ref.pts.size(), Vec2::Zero());
  const int n = static_cast<int>(ref.pts.size());
  for (int i = 0; i < n; ++i) {
    // Line fit (PCA) over beam-order neighbours close to the point.
    const Vec2& c = ref.pts[static_cast<std::size_t>(i)];
    const double range = (scan.pts[static_cast<std::size_t>(i)]).norm();
    const double reach = tuning.line_reach_m + tuning.line_reach_per_m * range;
    Vec2 mean = Vec2::Zero();
    int m = 0;
    for (int j = std::max(0, i - half); j <= std::min(n - 1, i + half); ++j) {
      if ((ref.pts[static_cast<std::size_t>(j)] - c).norm() <= reach) {
        mean += ref.pts[static_cast<std::size_t>(j)];
        ++m;
      }
    }
    if (m < 3) continue;
    mean /= m;
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (int j = std::max(0, i - half); j <= std::min(n - 1, i + half); ++j) {
      const Vec2 d = ref.pts[static_cast<std::size_t>(j)] - mean;
      if ((ref.pts[static_cast<std::size_t>(j)] - c).norm() <= reach) cov += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
    // A line: the smaller eigenvalue is much smaller than the larger one.
    if (es.eigenvalues()(0) > tuning.line_ratio * es.eigenvalues()(1)) continue;
    ref.normals[static_cast<std::size_t>(i)] = es.eigenvectors().col(0).normalized();
  }
  return ref;
}

struct IcpResult {
  double theta{0.0};
  Vec2 t{Vec2::Zero()};
  int iterations{0};
  double rms{0.0};
  std::size_t pairs{0};
  /// Smallest eigenvalue of the pairs' Σ w·n nᵀ (translation block) in the last
  /// iteration: how many effective pairs fix the least constrained direction.
  double min_information{0.0};
  bool converged{true};  ///< false when the solver says it did not converge (PCL)
};

/// Point-to-line ICP: finds (theta, t) with rot(theta)·src + t ≈ reference, starting
/// from the given guess. Huber-weighted Gauss–Newton, correspondences re-found each step.
IcpResult icpPointToLine(const Scan2D& src, const Reference& ref, const Grid2D& grid, double theta0,
                         const Vec2& t0, const AssemblerOptions& o, int stride) {
  IcpResult r;
  r.theta = theta0;
  r.t = t0;
  const AssemblerTuning& tn = o.tuning;
  const double huber = tn.huber_m;
  const double tukey = tn.tukey_m;
  for (int it = 0; it < o.max_iterations; ++it) {
    const Eigen::Matrix2d rot = rot2(r.theta);
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    double sse = 0.0;
    std::size_t pairs = 0;
    for (std::size_t i = 0; i < src.pts.size(); i += static_cast<std::size_t>(stride)) {
      const Vec2 rp = rot * src.pts[i];
      const Vec2 x = rp + r.t;
      const int j = grid.nearest(x);
      if (j < 0) continue;
      const Vec2& n = ref.normals[static_cast<std::size_t>(j)];
      if (n.squaredNorm() == 0.0) continue;
      // Compatible normals only: a point near a corner may be nearest to the other wall.
      if (!src.normals.empty()) {
        const Vec2& ns = src.normals[i];
        if (ns.squaredNorm() == 0.0 || std::abs(n.dot(rot * ns)) < tn.normal_cos) continue;
      }
      const double e = n.dot(x - ref.pts[static_cast<std::size_t>(j)]);
      const Vec2 drot(-rp.y(), rp.x());  // d(rot·p)/dθ
      const Eigen::Vector3d jac(n.x(), n.y(), n.dot(drot));
      // Huber for the first steps (the guess may be centimetres off), then Tukey:
      // pairs across an occlusion edge or a corner get no weight at all.
      double w = std::abs(e) <= huber ? 1.0 : huber / std::abs(e);
      if (it >= tn.huber_steps) {
        const double u = e / tukey;
        w = std::abs(u) < 1.0 ? (1.0 - u * u) * (1.0 - u * u) : 0.0;
      }
      h += w * jac * jac.transpose();
      g += w * jac * e;
      sse += e * e;
      ++pairs;
    }
    r.iterations = it + 1;
    r.pairs = pairs;
    r.rms = pairs ? std::sqrt(sse / static_cast<double>(pairs)) : 0.0;
    if (pairs < tn.min_pairs) break;
    r.min_information =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(h.topLeftCorner<2, 2>()).eigenvalues()(0);
    // A weak prior toward the guess (the previous position: the wind is a random
    // walk) keeps directions the scan does not constrain (one flat face seen, or
    // nothing in the field of view) where they were instead of letting them slide.
    const double lambda = tn.prior_weight * static_cast<double>(pairs);
    h(0, 0) += lambda;
    h(1, 1) += lambda;
    h(2, 2) += lambda;
    g(0) += lambda * (r.t.x() - t0.x());
    g(1) += lambda * (r.t.y() - t0.y());
    g(2) += lambda * (r.theta - theta0);
    // Degeneracy-aware step (Zhang et al., ICRA 2016): move only along directions
    // the pairs constrain. θ is scaled by a typical range so the eigenvalues compare.
    const Eigen::Vector3d scale(1.0, 1.0, 1.0 / tn.typical_range_m);
    const Eigen::Matrix3d hs = scale.asDiagonal() * h * scale.asDiagonal();
    const Eigen::Vector3d gs = scale.asDiagonal() * g;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(hs);
    const double floor_ev = tn.degenerate_fraction * es.eigenvalues().maxCoeff();
    Eigen::Vector3d dxs = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c) {
      const double ev = es.eigenvalues()(c);
      if (ev > floor_ev && ev > 0.0)
        dxs -= (es.eigenvectors().col(c).dot(gs) / ev) * es.eigenvectors().col(c);
    }
    const Eigen::Vector3d dx = scale.asDiagonal() * dxs;
    if (!dx.allFinite()) break;
    r.t += dx.head<2>();
    r.theta += dx(2);
    if (dx.head<2>().norm() < o.convergence_m && std::abs(dx(2)) < 1e-5) break;
  }
  return r;
}

/// The same problem with pcl::IterativeClosestPoint (point-to-point, 2D estimate).
IcpResult icpPcl(const Scan2D& src, const Reference& ref, double theta0, const Vec2& t0,
                 const AssemblerOptions& o, int stride) {
  using Cloud = pcl::PointCloud<pcl::PointXYZ>;
  auto s = std::make_shared<Cloud>();
  auto d = std::make_shared<Cloud>();
  for (std::size_t i = 0; i < src.pts.size(); i += static_cast<std::size_t>(stride)) {
    s->push_back(pcl::PointXYZ(static_cast<float>(src.pts[i].x()),
                               static_cast<float>(src.pts[i].y()), 0.0f));
  }
  for (const auto& p : ref.pts)
    d->push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.0f));
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
  icp.setTransformationEstimation(
      std::make_shared<
          pcl::registration::TransformationEstimation2D<pcl::PointXYZ, pcl::PointXYZ>>());
  icp.setInputSource(s);
  icp.setInputTarget(d);
  icp.setMaxCorrespondenceDistance(o.max_correspondence_m);
  icp.setMaximumIterations(o.max_iterations);
  icp.setTransformationEpsilon(o.convergence_m * o.convergence_m);
  Eigen::Matrix4f guess = Eigen::Matrix4f::Identity();
  guess.block<2, 2>(0, 0) = rot2(theta0).cast<float>();
  guess(0, 3) = static_cast<float>(t0.x());
  guess(1, 3) = static_cast<float>(t0.y());
  Cloud aligned;
  icp.align(aligned, guess);
  IcpResult r;
  const Eigen::Matrix4f m = icp.getFinalTransformation();
  r.theta = std::atan2(static_cast<double>(m(1, 0)), static_cast<double>(m(0, 0)));
  r.t = Vec2(static_cast<double>(m(0, 3)), static_cast<double>(m(1, 3)));
  r.iterations = o.max_iterations;  // PCL does not report the iterations it used
  r.rms = std::sqrt(std::max(0.0, icp.getFitnessScore(o.max_correspondence_m)));
  r.pairs = s->size();
  r.converged = icp.hasConverged();  // no correspondences, or no convergence in max_iterations
  return r;
}

/// Quaternion → rotation vector (log map), shortest path.
Eigen::Vector3d logMap(const Eigen::Quaterniond& q_in) {
  Eigen::Quaterniond q = q_in.w() < 0.0 ? Eigen::Quaterniond(-q_in.coeffs()) : q_in;
  const Eigen::AngleAxisd aa(q);
  return aa.angle() * aa.axis();
}

Eigen::Quaterniond expMap(const Eigen::Vector3d& v) {
  const double a = v.norm();
  if (a < 1e-12) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, v / a));
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
  if (max_iterations < 1)
    throw InputError(where + ": max_iterations must be >= 1, got " +
                     std::to_string(max_iterations));
  requirePositive(max_correspondence_m, where, "max_correspondence_m");
  requirePositive(convergence_m, where, "convergence_m");
  requirePositive(keyframe_yaw_deg, where, "keyframe_yaw_deg");
  requirePositive(keyframe_translation_m, where, "keyframe_translation_m");
  if (horizontal_stride < 1)
    throw InputError(where + ": horizontal_stride must be >= 1, got " +
                     std::to_string(horizontal_stride));
  if (!(imu_smoothing_s >= 0.0) || !std::isfinite(imu_smoothing_s)) {
    throw InputError(where + ": imu_smoothing_s must be >= 0, got " +
                     formatNumber(imu_smoothing_s));
  }
  requirePositive(max_imu_gap_s, where, "max_imu_gap_s");
  if (!(z_cone_deg > 0.0 && z_cone_deg < 90.0))
    throw InputError(where + ": z_cone_deg must be in (0, 90), got " + formatNumber(z_cone_deg));
  if (!(drift_segment_deg > 0.0 && drift_segment_deg <= 360.0)) {
    throw InputError(where + ": drift_segment_deg must be in (0, 360], got " +
                     formatNumber(drift_segment_deg));
  }
  if (drift_iterations < 1)
    throw InputError(where + ": drift_iterations must be >= 1, got " +
                     std::to_string(drift_iterations));
  requirePositive(drift_voxel_m, where, "drift_voxel_m");
  tuning.validate(where + ".tuning");
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

double yawOf(const Eigen::Quaterniond& q) {
  const Vec3 x = q * Vec3::UnitX();
  return std::atan2(x.y(), x.x());
}

ImuTrack::ImuTrack(const std::vector<ImuSample>& samples, double max_gap_s, double smoothing_s,
                   const std::string& where) {
  if (samples.empty()) throw InputError(where + ": no IMU samples");
  t_.reserve(samples.size());
  q_.reserve(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto& s = samples[i];
    if (!std::isfinite(s.t_s) || !s.world_q_body.coeffs().allFinite() ||
        s.world_q_body.norm() < 1e-6) {
      throw InputError(where + ": IMU sample " + std::to_string(i) +
                       " is not finite or not a rotation");
    }
    if (i > 0) {
      const double gap = s.t_s - t_.back();
      if (gap < 0.0) {
        throw InputError(where + ": IMU time goes backwards at sample " + std::to_string(i) + " (" +
                         formatNumber(t_.back()) + " s -> " + formatNumber(s.t_s) + " s)");
      }
      if (gap > max_gap_s) {
        throw InputError(where + ": IMU gap of " + formatNumber(gap) +
                         " s at t = " + formatNumber(t_.back()) +
                         " s is longer than max_imu_gap_s " + formatNumber(max_gap_s) + " s");
      }
    }
    t_.push_back(s.t_s);
    Eigen::Quaterniond q = s.world_q_body.normalized();
    if (!q_.empty() && q_.back().coeffs().dot(q.coeffs()) < 0.0)
      q.coeffs() *= -1.0;  // same hemisphere
    q_.push_back(q);
  }
  if (smoothing_s > 0.0 && q_.size() > 2) {
    std::vector<Eigen::Quaterniond> smooth(q_.size());
    std::size_t lo = 0, hi = 0;
    for (std::size_t i = 0; i < q_.size(); ++i) {
      while (t_[lo] < t_[i] - 0.5 * smoothing_s) ++lo;
      while (hi + 1 < q_.size() && t_[hi + 1] <= t_[i] + 0.5 * smoothing_s) ++hi;
      // Least-squares line r(τ) = a + b·τ through the rotation vectors relative to q_i.
      const Eigen::Quaterniond inv = q_[i].conjugate();
      double s0 = 0, s1 = 0, s2 = 0;
      Eigen::Vector3d r0 = Eigen::Vector3d::Zero(), r1 = Eigen::Vector3d::Zero();
      for (std::size_t j = lo; j <= hi; ++j) {
        const double tau = t_[j] - t_[i];
        const Eigen::Vector3d r = logMap(inv * q_[j]);
        s0 += 1.0;
        s1 += tau;
        s2 += tau * tau;
        r0 += r;
        r1 += tau * r;
      }
      const double det = s0 * s2 - s1 * s1;
      const Eigen::Vector3d a = std::abs(det) > 1e-18 ? Eigen::Vector3d((s2 * r0 - s1 * r1) / det)
                                                      : Eigen::Vector3d(r0 / s0);
      smooth[i] = (q_[i] * expMap(a)).normalized();
    }
    q_ = std::move(smooth);
    for (std::size_t i = 1; i < q_.size(); ++i) {
      if (q_[i - 1].coeffs().dot(q_[i].coeffs()) < 0.0) q_[i].coeffs() *= -1.0;
    }
  }
  // The per-interval part of Eigen's slerp (its dot, acos and sin), once per sample
  // instead of once per beam.
  slerp_.resize(q_.size() > 1 ? q_.size() - 1 : 0);
  for (std::size_t i = 0; i + 1 < q_.size(); ++i) {
    Slerp& s = slerp_[i];
    s.dot = q_[i].dot(q_[i + 1]);
    s.theta = std::acos(std::abs(s.dot));
    s.sin_theta = std::sin(s.theta);
  }
}

Eigen::Quaterniond ImuTrack::at(double t_s) const {
  if (t_s <= t_.front()) return q_.front();
  if (t_s >= t_.back()) return q_.back();
  const auto it = std::upper_bound(t_.begin(), t_.end(), t_s);
  const auto j = static_cast<std::size_t>(it - t_.begin());
  const std::size_t i = j - 1;
  const double dt = t_[j] - t_[i];
  const double u = dt > 0.0 ? (t_s - t_[i]) / dt : 0.0;
  // Eigen's QuaternionBase::slerp (3.4), term for term, with the interval's cached.
  const Slerp& s = slerp_[i];
  double scale0 = 1.0 - u;
  double scale1 = u;
  if (std::abs(s.dot) < 1.0 - std::numeric_limits<double>::epsilon()) {
    scale0 = std::sin((1.0 - u) * s.theta) / s.sin_theta;
    scale1 = std::sin(u * s.theta) / s.sin_theta;
  }
  if (s.dot < 0.0) scale1 = -scale1;
  return Eigen::Quaterniond(scale0 * q_[i].coeffs() + scale1 * q_[j].coeffs());
}

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
  const Grid2D lgrid(lref.pts, options.max_correspondence_m);
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
  auto grid = std::make_unique<Grid2D>(ref.pts, options.max_correspondence_m);
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
      grid = std::make_unique<Grid2D>(ref.pts, options.max_correspondence_m);
      ++stats.keyframes;
    }
  }
  if (loop_closure) odometryLoopClosure(scans, odo, options);
  stats.mean_icp_iterations = icp_runs ? iter_sum / static_cast<double>(icp_runs) : 0.0;
  stats.mean_icp_rms_m = icp_runs ? rms_sum / static_cast<double>(icp_runs) : 0.0;
}

/// Vertical drift z per vertical scan from the nadir/zenith beams (0 without
/// estimate_z): each scan's height offset against height maps of the ground below
/// and the ceiling above built from the scans before it. `xy` places the beams.
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

/// Index of the vertical scan starting nearest to time t (scans non-empty).
std::size_t nearestVerticalScan(const std::vector<LaserScan>& vertical, double t) {
  const auto it = std::lower_bound(vertical.begin(), vertical.end(), t,
                                   [](const LaserScan& s, double v) { return s.t_start_s < v; });
  std::size_t j = static_cast<std::size_t>(it - vertical.begin());
  if (j == vertical.size() || (j > 0 && t - vertical[j - 1].t_start_s < vertical[j].t_start_s - t))
    j = j == 0 ? 0 : j - 1;
  return j;
}

/// T(t) from the odometry (xy at the horizontal scans' mid times) and the vertical
/// drift (z of the vertical scan nearest in time). Without horizontal scans: the
/// vertical scans' start times, z only.
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

/// The joint refinement of T(t) (drift_refinement.h) on `track`, in place; returns it.
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
