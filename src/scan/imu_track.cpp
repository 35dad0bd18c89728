// The IMU's rotation R(t) of stage 1 (paper §II-A): samples checked, optionally
// smoothed, interpolated by slerp (scan/station_assembler.h, ImuTrack).

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/scan/station_assembler.h"

namespace uavip::scan {
namespace {

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

}  // namespace

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

}  // namespace uavip::scan
