// GCC 12 reports false positives (-Warray-bounds, -Wmaybe-uninitialized) inside the
// Eigen/SSE code that PCL's registration templates instantiate here (set before any
// include: the warnings are attributed to the Eigen headers).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Warray-bounds"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

// Stage 1's 2D ICP (paper §II-A): a horizontal scan against a keyframe map, by uavip's
// point-to-line Gauss-Newton or by PCL's point-to-point ICP (scan.icp).

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/transformation_estimation_2D.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <memory>

#include "assembler_steps.h"

namespace uavip::scan {

Eigen::Matrix2d rot2(double theta) {
  Eigen::Matrix2d r;
  const double c = std::cos(theta), s = std::sin(theta);
  r << c, -s, s, c;
  return r;
}

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

IcpResult icpPointToLine(const Scan2D& src, const Reference& ref, const ScanGrid& grid,
                         double theta0, const Vec2& t0, const AssemblerOptions& o, int stride) {
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

}  // namespace uavip::scan
