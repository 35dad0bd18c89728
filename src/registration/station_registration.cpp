// GCC 12 reports false positives (-Warray-bounds, -Wmaybe-uninitialized) inside the
// Eigen/SSE code that PCL's registration templates instantiate here (set before any
// include: the warnings are attributed to the Eigen headers).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Warray-bounds"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "uavip/registration/station_registration.h"

#include <pcl/features/normal_3d.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>
#include <pcl/search/kdtree.h>
#include <sys/mman.h>
#include <unistd.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <new>
#include <queue>
#include <sstream>
#include <unordered_set>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/key_sort.h"
#include "uavip/core/memory.h"
#include "uavip/core/neighbour_index.h"
#include "uavip/core/parallel.h"
#include "uavip/core/pcl_cloud.h"
#include "uavip/core/stopwatch.h"
#include "uavip/core/text.h"
#include "uavip/core/voxel_key.h"

namespace uavip::registration {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using NormalCloud = pcl::PointCloud<pcl::PointNormal>;

constexpr const char* kNothingToRegister =
    "registration: every station cloud is empty, nothing to register";

/// Centroid of each occupied voxel, voxels in key order (deterministic). Sorting
/// (key, index) pairs instead of a hash map: about five times faster on large clouds
/// (docs/architecture_notes.md, "Figures behind the code").
/// Kept apart from core's voxelDownsample on purpose: the same voxels, but another
/// order (z fastest here, x fastest there) and plain centroid sums (core's are taken
/// relative to a voxel's first point). Both reach the merged cloud, and with core's
/// the bridge's sequential RANSAC finds 9 surfaces instead of 14 (measured): the
/// order sensitivity is the detector's to fix, not a reason to change outputs here.
/// On two threads: the keys by slices, the pairs sorted in two halves and merged
/// (core/key_sort.h), the centroids in two halves cut between voxels. The output is
/// the one-thread output, bit for bit.
PointList voxelDownsample(const PointList& points, double leaf, int threads) {
  if (leaf <= 0.0 || points.empty()) return points;
  // Keys in the world lattice's order (as this stage always sorted); the keyer checks
  // that the cloud spans at most 2^21 voxels per axis, so no two voxels share a key.
  (void)VoxelKeyer::forPointsOnLattice(points, leaf, "registration.downsample_m/output_voxel_m");
  const std::size_t n = points.size();
  constexpr std::size_t kSlice = 1 << 16;
  std::vector<KeyedIndex> keyed(n);
  parallelFor((n + kSlice - 1) / kSlice, threads, [&](std::size_t slice, std::size_t) {
    const std::size_t end = std::min(n, (slice + 1) * kSlice);
    for (std::size_t i = slice * kSlice; i < end; ++i) {
      keyed[i] = {VoxelKeyer::wrappedKey(VoxelKeyer::latticeIndex(points[i], leaf)),
                  static_cast<std::uint32_t>(i)};
    }
  });
  sortByKey(keyed, threads);  // = std::sort on the pairs (indices ascend), faster
  // Centroids of the voxels in [from, to) of `keyed` (whole voxels), one per voxel.
  const auto centroids = [&](std::size_t from, std::size_t to) {
    PointList out;
    for (std::size_t i = from; i < to;) {
      Vec3 sum = Vec3::Zero();
      std::size_t j = i;
      for (; j < to && keyed[j].first == keyed[i].first; ++j) sum += points[keyed[j].second];
      out.push_back(sum / static_cast<double>(j - i));
      i = j;
    }
    return out;
  };
  return fromRunsInHalves(keyed, threads, centroids);
}

/// PCA normals of a cloud from its k nearest neighbours (PCL NormalEstimation on a
/// kd-tree); unoriented, NaN where undefined.
pcl::PointCloud<pcl::Normal> pclNormals(const Cloud::Ptr& cloud, int k) {
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  ne.setInputCloud(cloud);
  ne.setSearchMethod(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  ne.setKSearch(k);
  pcl::PointCloud<pcl::Normal> normals;
  ne.compute(normals);
  return normals;
}

/// The points of cloud with finite normals (k neighbours), as PointNormals.
NormalCloud::Ptr withNormals(const Cloud::Ptr& cloud, int k) {
  const pcl::PointCloud<pcl::Normal> normals = pclNormals(cloud, k);
  auto out = std::make_shared<NormalCloud>();
  out->points.reserve(cloud->size());
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    pcl::PointNormal pn;
    pn.x = (*cloud)[i].x;
    pn.y = (*cloud)[i].y;
    pn.z = (*cloud)[i].z;
    pn.normal_x = normals[i].normal_x;
    pn.normal_y = normals[i].normal_y;
    pn.normal_z = normals[i].normal_z;
    pn.curvature = normals[i].curvature;
    if (!std::isfinite(pn.normal_x)) continue;  // too few neighbours
    out->points.push_back(pn);
  }
  out->width = static_cast<std::uint32_t>(out->points.size());
  out->height = 1;
  return out;
}

/// The points (and their normals) inside box.
void insideBox(const PointList& points, const std::vector<Vec3>& normals, const Aabb& box,
               PointList& out, std::vector<Vec3>& out_normals) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    if ((p.array() >= box.min.array()).all() && (p.array() <= box.max.array()).all()) {
      out.push_back(p);
      out_normals.push_back(normals[i]);
    }
  }
}

Aabb grown(Aabb box, double margin) {
  box.min.array() -= margin;
  box.max.array() += margin;
  return box;
}

struct Alignment {
  Eigen::Isometry3d delta{
      Eigen::Isometry3d::Identity()};  ///< maps source (world guess) onto target
  bool converged{false};
  double rms{0.0};
  int iterations{0};
  std::size_t pairs{0};
  Vec3 information{Vec3::Zero()};
  Eigen::Matrix3d directions{Eigen::Matrix3d::Identity()};
};

/// Dense occupancy bitmap of a cloud on a grid of `step`, for O(1) hit tests.
class Occupancy {
 public:
  Occupancy(const PointList& points, double step) : step_(step) {
    box_ = boundingBox(points);
    box_.min.array() -= step;
    box_.max.array() += step;
    dims_ = ((box_.max - box_.min) / step).array().ceil().cast<int>().max(1);
    const double cells = static_cast<double>(dims_.x()) * dims_.y() * dims_.z();
    if (points.empty() || cells > 5e7) return;  // too fine for the extent: no search
    bits_.assign(static_cast<std::size_t>(cells), 0);
    for (const auto& p : points) {
      std::size_t k = 0;
      if (index(p, k)) bits_[k] = 1;
    }
  }
  bool usable() const { return !bits_.empty(); }
  bool hit(const Vec3& p) const {
    std::size_t k = 0;
    return index(p, k) && bits_[k];
  }

 private:
  bool index(const Vec3& p, std::size_t& out) const {
    const Eigen::Vector3d c = (p - box_.min) / step_;
    if ((c.array() < 0.0).any()) return false;
    const Eigen::Vector3i i = c.array().floor().cast<int>();
    if ((i.array() >= dims_.array()).any()) return false;
    out = (static_cast<std::size_t>(i.z()) * static_cast<std::size_t>(dims_.y()) +
           static_cast<std::size_t>(i.y())) *
              static_cast<std::size_t>(dims_.x()) +
          static_cast<std::size_t>(i.x());
    return true;
  }
  double step_;
  Aabb box_;
  Eigen::Vector3i dims_{1, 1, 1};
  std::vector<std::uint8_t> bits_;
};

/// PCA normals (k neighbours) of a cloud, oriented toward `viewpoint` (the station
/// that saw the points); NaN where undefined.
std::vector<Vec3> normalsOf(const PointList& points, const Vec3& viewpoint, int k) {
  const pcl::PointCloud<pcl::Normal> normals = pclNormals(toPclCloud(points, Vec3::Zero()), k);
  std::vector<Vec3> out(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    out[i] = Vec3(normals[i].normal_x, normals[i].normal_y, normals[i].normal_z);
    if (out[i].dot(viewpoint - points[i]) < 0.0) out[i] = -out[i];
  }
  return out;
}

/// Points whose (oriented) normal is within acos(min_cos) of axis.
PointList facing(const PointList& points, const std::vector<Vec3>& normals, const Vec3& axis,
                 double min_cos) {
  PointList out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (normals[i].allFinite() && normals[i].dot(axis) > min_cos) out.push_back(points[i]);
  }
  return out;
}

/// Number of (strided, ≤ ~3000) source points that land in occupied target cells.
int hits(const PointList& source, const Occupancy& target, const Vec3& offset) {
  const std::size_t stride = std::max<std::size_t>(1, source.size() / 3000);
  int h = 0;
  for (std::size_t i = 0; i < source.size(); i += stride)
    h += target.hit(source[i] + offset) ? 1 : 0;
  return h;
}

/// Coarse translation search (the rotation is known from the IMU). An offset along
/// a direction is seen only by surfaces facing it (a long wall looks the same when
/// slid along itself and would drown the signal), so the search is three 1D searches,
/// each on the points whose normals face its axis: the two principal horizontal
/// directions of the upright surfaces' normals (walls, piers) and z (ground, deck),
/// twice round. Each tests offsets within ±radius on a grid of `step` and keeps the
/// one that puts most points into occupied target cells; ties go to the smaller
/// offset (the recorded positions are a prior).
Vec3 searchTranslation(const PointList& source, const std::vector<Vec3>& ns,
                       const PointList& target, const std::vector<Vec3>& nt, double radius,
                       double step, int threads) {
  // Principal horizontal directions of the target's upright normals.
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& n : nt) {
    if (n.allFinite() && std::abs(n.z()) < 0.5) scatter += n.head<2>() * n.head<2>().transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(scatter);
  Vec3 axes[3] = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
  if (scatter.trace() > 0.0) {
    axes[0] = Vec3(es.eigenvectors()(0, 1), es.eigenvectors()(1, 1), 0.0).normalized();
    axes[1] = Vec3(-axes[0].y(), axes[0].x(), 0.0);
  }
  const int n = static_cast<int>(std::round(radius / step));
  Vec3 offset = Vec3::Zero();
  for (int round = 0; round < 2; ++round) {
    for (const auto& axis : axes) {
      // Faces toward +axis and toward −axis separately: the two faces of a pier are
      // both "x-facing" but must not be matched with each other.
      const double min_cos = axis.z() > 0.5 ? 0.8 : 0.7;
      const PointList src_pos = facing(source, ns, axis, min_cos),
                      src_neg = facing(source, ns, -axis, min_cos);
      const Occupancy occ_pos(facing(target, nt, axis, min_cos), step);
      const Occupancy occ_neg(facing(target, nt, -axis, min_cos), step);
      const bool use_pos = src_pos.size() >= 10 && occ_pos.usable();
      const bool use_neg = src_neg.size() >= 10 && occ_neg.usable();
      if (!use_pos && !use_neg) continue;
      auto score = [&](const Vec3& o) {
        return (use_pos ? hits(src_pos, occ_pos, o) : 0) +
               (use_neg ? hits(src_neg, occ_neg, o) : 0);
      };
      const double along = offset.dot(axis);
      const Vec3 base = offset - along * axis;
      double best_t = along;
      int best = score(offset);
      // The scores on every core (each reads only), the choice in offset order.
      std::vector<int> scores(static_cast<std::size_t>(2 * n + 1));
      parallelFor(scores.size(), threads, [&](std::size_t k, std::size_t) {
        scores[k] = score(base + (static_cast<int>(k) - n) * step * axis);
      });
      for (int i = -n; i <= n; ++i) {
        const double t = i * step;
        const int at = i + n;  // offsets from −n
        const int h = scores[static_cast<std::size_t>(at)];
        if (h > best || (h == best && std::abs(t) < std::abs(best_t))) {
          best = h;
          best_t = t;
        }
      }
      offset = base + best_t * axis;
    }
  }
  return offset;
}

/// Normal-space sampling (Rusinkiewicz & Levoy 2001) reduced to two bins: every
/// point on an upright surface (|n_z| < 0.7: walls, piers, trunks — the only ones
/// that fix x and y) and an even stride of the level ones (ground, deck), at most
/// as many as the upright ones and never fewer than `min_level`. On a bridge the
/// level points are ~97 % of the cloud: sampled as they come they would drown the
/// few that fix the horizontal position (and cost most of the ICP's time).
std::vector<std::size_t> balancedSample(const std::vector<Vec3>& normals, std::size_t min_level) {
  std::vector<std::size_t> upright, level;
  for (std::size_t i = 0; i < normals.size(); ++i) {
    if (!normals[i].allFinite()) continue;
    (std::abs(normals[i].z()) < 0.7 ? upright : level).push_back(i);
  }
  const std::size_t keep = std::min(level.size(), std::max(upright.size(), min_level));
  std::vector<std::size_t> out = upright;
  for (std::size_t k = 0; k < keep; ++k) out.push_back(level[k * level.size() / keep]);
  std::sort(out.begin(), out.end());
  return out;
}

/// What the translation-only ICP found.
struct IcpOutcome {
  Vec3 t{Vec3::Zero()};
  double rms{0.0};
  bool converged{false};
  int iterations{0};
  std::size_t pairs{0};
  Vec3 information{Vec3::Zero()};  ///< eigenvalues of Σ w·n nᵀ, ascending [effective pairs]
  Eigen::Matrix3d directions{Eigen::Matrix3d::Identity()};  ///< their eigenvectors (columns)
};

/// Translation-only point-to-plane ICP (the rotation is the IMU's): minimises
/// Σ w·(n_q·(p + t − q))² over t with Tukey weights, re-pairing every step. A pair
/// needs the two normals within 45° (each oriented toward the station that saw it:
/// the two faces of a thin object seen from opposite sides must not pair). The step
/// moves only along directions the pairs constrain (eigenvalues of Σ w·n nᵀ ≥ 2 % of
/// the largest and ≥ kMinInformationPairs effective pairs); the others keep the start.
IcpOutcome icpTranslation(const PointList& source, const std::vector<Vec3>& source_normals,
                          const NeighbourIndex& tree, const std::vector<Vec3>& target_normals,
                          double gate, int iterations, int threads) {
  const PointList& target = tree.cloud();
  const std::vector<std::size_t> sample = balancedSample(source_normals, 2000);
  std::vector<int> nearest(sample.size());
  std::vector<float> nearest_d2(sample.size());
  IcpOutcome out;
  for (int it = 0; it < iterations; ++it) {
    const double c = it < 5 ? gate : std::max(0.1, 0.3 * gate);  // Tukey scale: wide, then tight
    // The pairs' searches on every core, in blocks; the sums below in sample order.
    constexpr std::size_t kBlock = 512;
    parallelFor((sample.size() + kBlock - 1) / kBlock, threads, [&](std::size_t b, std::size_t) {
      const std::size_t end = std::min(sample.size(), (b + 1) * kBlock);
      for (std::size_t k = b * kBlock; k < end; ++k)
        nearest[k] = tree.nearestTo(source[sample[k]] + out.t, &nearest_d2[k]);
    });
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    Vec3 g = Vec3::Zero();
    double sse = 0.0;
    std::size_t pairs = 0;
    for (std::size_t k = 0; k < sample.size(); ++k) {
      const std::size_t i = sample[k];
      const Vec3 p = source[i] + out.t;
      if (nearest[k] < 0 || nearest_d2[k] > gate * gate) continue;
      const auto j = static_cast<std::size_t>(nearest[k]);
      const Vec3& n = target_normals[j];
      if (!n.allFinite() || !(n.dot(source_normals[i]) > 0.7)) continue;
      const double e = n.dot(p - target[j]);
      const double u = e / c;
      if (std::abs(u) >= 1.0) continue;
      const double w = (1.0 - u * u) * (1.0 - u * u);
      h += w * n * n.transpose();
      g += w * e * n;
      sse += e * e;
      ++pairs;
    }
    if (pairs < 30) return out;
    out.rms = std::sqrt(sse / static_cast<double>(pairs));
    out.pairs = pairs;
    out.iterations = it + 1;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(h);
    out.information = es.eigenvalues();
    out.directions = es.eigenvectors();
    const double floor_ev = std::max(kMinInformationPairs, 0.02 * es.eigenvalues().maxCoeff());
    Vec3 dt = Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
      const double ev = es.eigenvalues()(k);
      if (ev >= floor_ev) dt -= (es.eigenvectors().col(k).dot(g) / ev) * es.eigenvectors().col(k);
    }
    out.t += dt;
    out.converged = true;
    if (dt.norm() < 2e-4 && it >= 6) break;
  }
  return out;
}

/// Sets a PCL registration's clouds, iteration limit and convergence epsilon.
template <typename Registration, typename CloudPtr>
void setUp(Registration& reg, const CloudPtr& src, const CloudPtr& tgt, int iterations,
           double epsilon) {
  reg.setInputSource(src);
  reg.setInputTarget(tgt);
  reg.setMaximumIterations(iterations);
  reg.setTransformationEpsilon(epsilon);
}

/// A PCL registration's outcome: returns the transform, and sets converged and the
/// fitness (mean squared pair distance within the options' gate).
template <typename Registration>
Eigen::Matrix4f outcome(Registration& reg, const RegistrationOptions& o, bool& converged,
                        double& fitness) {
  converged = reg.hasConverged();
  fitness = reg.getFitnessScore(o.max_correspondence_m);
  return reg.getFinalTransformation();
}

/// PCL's ICP or GICP on XYZ clouds with the options' gate and iterations.
template <typename Registration>
Eigen::Matrix4f alignPointToPoint(Registration& reg, const Cloud::Ptr& src, const Cloud::Ptr& tgt,
                                  const RegistrationOptions& o, bool& converged, double& fitness) {
  setUp(reg, src, tgt, o.max_iterations, 1e-8);
  reg.setMaxCorrespondenceDistance(o.max_correspondence_m);
  Cloud out;
  reg.align(out);
  return outcome(reg, o, converged, fitness);
}

/// PCL's point-to-plane ICP on the clouds with normals (pcl_normal_k neighbours),
/// coarse to fine: the configured gate, then a quarter of it.
Eigen::Matrix4f alignPointToPlane(const Cloud::Ptr& src, const Cloud::Ptr& tgt,
                                  const RegistrationOptions& o, bool& converged, double& fitness) {
  pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal> icp;
  setUp(icp, withNormals(src, o.pcl_normal_k), withNormals(tgt, o.pcl_normal_k), o.max_iterations,
        1e-8);
  NormalCloud out;
  icp.setMaxCorrespondenceDistance(o.max_correspondence_m);
  icp.align(out);
  Eigen::Matrix4f guess = icp.getFinalTransformation();
  icp.setMaxCorrespondenceDistance(0.25 * o.max_correspondence_m);
  icp.align(out, guess);
  return outcome(icp, o, converged, fitness);
}

/// PCL's NDT at the options' resolution.
Eigen::Matrix4f alignNdt(const Cloud::Ptr& src, const Cloud::Ptr& tgt, const RegistrationOptions& o,
                         bool& converged, double& fitness) {
  pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ> ndt;
  setUp(ndt, src, tgt, o.max_iterations, 1e-6);
  ndt.setResolution(static_cast<float>(o.ndt_resolution_m));
  ndt.setStepSize(0.1);
  Cloud out;
  ndt.align(out);
  return outcome(ndt, o, converged, fitness);
}

/// One of PCL's registrations (o.method) of src onto tgt; identity for the methods
/// that are not PCL's.
Eigen::Matrix4f alignWithPcl(const Cloud::Ptr& src, const Cloud::Ptr& tgt,
                             const RegistrationOptions& o, bool& converged, double& fitness) {
  switch (o.method) {
    case Method::None:
    case Method::PointToPlaneTranslation:
      break;
    case Method::Icp: {
      pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
      return alignPointToPoint(icp, src, tgt, o, converged, fitness);
    }
    case Method::IcpPointToPlane:
      return alignPointToPlane(src, tgt, o, converged, fitness);
    case Method::Gicp: {
      pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
      return alignPointToPoint(icp, src, tgt, o, converged, fitness);
    }
    case Method::Ndt:
      return alignNdt(src, tgt, o, converged, fitness);
  }
  return Eigen::Matrix4f::Identity();
}

/// The translation-only ICP's result as an alignment, after the coarse offset.
Alignment translationAlignment(const Vec3& coarse, const IcpOutcome& r) {
  Alignment a;
  a.delta = Eigen::Translation3d(coarse + r.t) * Eigen::Isometry3d::Identity();
  a.converged = r.converged;
  a.rms = r.rms;
  a.iterations = r.iterations;
  a.pairs = r.pairs;
  a.information = r.information;
  a.directions = r.directions;
  return a;
}

/// PCL's registration of source (moved by coarse) onto target, worked around the
/// target's centroid (floats keep sub-millimetre precision there).
Alignment pclAlignment(const PointList& source, const PointList& target, const Vec3& coarse,
                       const RegistrationOptions& o) {
  Alignment a;
  Vec3 origin = Vec3::Zero();
  for (const auto& p : target) origin += p;
  origin /= static_cast<double>(target.size());
  const Cloud::Ptr src = toPclCloud(source, origin), tgt = toPclCloud(target, origin);
  double fitness = 0.0;
  const Eigen::Matrix4f m = alignWithPcl(src, tgt, o, a.converged, fitness);
  const Eigen::Isometry3d d(m.cast<double>());
  // Back from centroid coordinates: x_world' = origin + d·(x_world − origin).
  a.delta = Eigen::Translation3d(origin) * d * Eigen::Translation3d(-origin) *
            Eigen::Translation3d(coarse);
  // Re-orthonormalise the float rotation.
  const Eigen::Quaterniond q(a.delta.linear());
  a.delta.linear() = q.normalized().toRotationMatrix();
  a.rms = std::sqrt(std::max(0.0, fitness));
  return a;
}

/// Aligns source onto target (both in world coordinates, source at its guess):
/// coarse translation only (rotation known from the IMU), then ICP from there.
Alignment align(const PointList& source_in, const std::vector<Vec3>& source_normals,
                const PointList& target, const std::vector<Vec3>& target_normals,
                const RegistrationOptions& o) {
  if (source_in.size() < 10 || target.size() < 10) return {};
  // The ICP's kd-tree over the target is built beside the coarse search. Floats in
  // the world frame (origin 0), as this stage always searched.
  std::future<std::unique_ptr<const NeighbourIndex>> tree;
  if (o.method == Method::PointToPlaneTranslation) {
    tree = std::async(o.threads > 1 ? std::launch::async : std::launch::deferred, [&target] {
      return std::make_unique<const NeighbourIndex>(target, Vec3::Zero());
    });
  }
  const Vec3 coarse = o.search_radius_m > 0.0
                          ? searchTranslation(source_in, source_normals, target, target_normals,
                                              o.search_radius_m, o.search_step_m, o.threads)
                          : Vec3::Zero();
  PointList source = source_in;
  for (auto& p : source) p += coarse;
  if (o.method == Method::PointToPlaneTranslation) {
    return translationAlignment(
        coarse, icpTranslation(source, source_normals, *tree.get(), target_normals,
                               o.max_correspondence_m, o.max_iterations, o.threads));
  }
  if (o.method == Method::None) return {};
  return pclAlignment(source, target, coarse, o);
}

PointList transformed(const PointList& points, const Eigen::Isometry3d& pose) {
  PointList out;
  out.reserve(points.size());
  for (const auto& p : points) out.push_back(pose * p);
  return out;
}

}  // namespace

Method methodFromString(const std::string& name) {
  if (name == "none") return Method::None;
  if (name == "translation") return Method::PointToPlaneTranslation;
  if (name == "icp") return Method::Icp;
  if (name == "icp_point_to_plane") return Method::IcpPointToPlane;
  if (name == "gicp") return Method::Gicp;
  if (name == "ndt") return Method::Ndt;
  throw InputError(
      "registration: method must be none, translation, icp, icp_point_to_plane, gicp or ndt, got "
      "'" +
      name + "'");
}

std::string toString(Method method) {
  switch (method) {
    case Method::None:
      return "none";
    case Method::PointToPlaneTranslation:
      return "translation";
    case Method::Icp:
      return "icp";
    case Method::IcpPointToPlane:
      return "icp_point_to_plane";
    case Method::Gicp:
      return "gicp";
    case Method::Ndt:
      return "ndt";
  }
  return "?";
}

void RegistrationOptions::validate(const std::string& where) const {
  table().check(*this, where);
  if (threads < 1)
    throw InputError(where + ": threads must be >= 1, got " + std::to_string(threads));
  requireThat(recent_stations >= 1, where, "recent_stations", ">= 1", recent_stations);
}

const params::Table<RegistrationOptions>& RegistrationOptions::table() {
  static const params::Table<RegistrationOptions> t = [] {
    using O = RegistrationOptions;
    params::Table<O> p;
    std::vector<std::string> methods;
    for (const Method m : {Method::None, Method::PointToPlaneTranslation, Method::Icp,
                           Method::IcpPointToPlane, Method::Gicp, Method::Ndt})
      methods.push_back(toString(m));
    p.add(
         "method", params::Kind::Text,
         [](const O& o) { return params::toValue(toString(o.method)); },
         [](O& o, const params::Value& v) { o.method = methodFromString(v.text); },
         "stage 2's algorithm (translation: uavip's point-to-plane translation; the others PCL's)")
        .oneOf(methods)
        .storedAt([](const O& o) -> const void* { return &o.method; });
    p.add("overlap_margin_m", &O::overlap_margin_m,
          "growth of the bounding boxes that predict the overlap")
        .unitIs("m")
        .atLeast(0);
    p.add("search_radius_m", &O::search_radius_m,
          "coarse translation search around the recorded position, ± this per axis (0: none)")
        .unitIs("m")
        .atLeast(0);
    p.add("search_step_m", &O::search_step_m, "the coarse search's grid step and occupancy cell")
        .unitIs("m")
        .positive();
    p.add("downsample_m", &O::downsample_m, "voxel edge of the clouds ICP sees")
        .unitIs("m")
        .positive();
    p.add("max_correspondence_m", &O::max_correspondence_m, "ICP pairs farther apart are rejected")
        .unitIs("m")
        .positive();
    p.add("max_iterations", &O::max_iterations, "ICP iterations").atLeast(1);
    p.add("ndt_resolution_m", &O::ndt_resolution_m, "NDT cell").unitIs("m").positive();
    p.add("use_recorded_yaw", &O::use_recorded_yaw,
          "rotate each station by its recorded yaw minus the IMU's at its first scan");
    p.add("output_voxel_m", &O::output_voxel_m,
          "the merged cloud down-sampled to this voxel (0: keep every point)")
        .unitIs("m")
        .atLeast(0);
    p.add("normal_k", &O::normal_k, "neighbours of a point's PCA normal (method translation)")
        .atLeast(3);
    p.add("pcl_normal_k", &O::pcl_normal_k, "the same for PCL's icp_point_to_plane").atLeast(3);
    return p;
  }();
  return t;
}

Eigen::Isometry3d initialStationPose(const RawLog& log, std::size_t index, bool use_recorded_yaw,
                                     double imu_yaw_rad, double imu_yaw0_rad) {
  if (index >= log.stations.size()) {
    throw InputError("registration: station index " + std::to_string(index) + " out of range");
  }
  const Station& s0 = log.stations.front();
  const Station& s = log.stations[index];
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = s.recorded_position - s0.recorded_position;
  if (use_recorded_yaw) {
    // Station frames use the IMU's heading reference; turn each onto the recorded headings.
    const double d = (s.recorded_yaw_rad - imu_yaw_rad) - (s0.recorded_yaw_rad - imu_yaw0_rad);
    pose.linear() = Eigen::AngleAxisd(d, Vec3::UnitZ()).toRotationMatrix();
  }
  return pose;
}

namespace {

/// Index of the first station with points (the reference); throws InputError when
/// there is none.
std::size_t referenceStation(const std::vector<StationInput>& stations) {
  for (std::size_t i = 0; i < stations.size(); ++i) {
    if (!stations[i].points.empty()) return i;
  }
  throw InputError(kNothingToRegister);
}

}  // namespace

// Types StationMerger::State holds: in a named namespace (a member of a class with
// linkage may not have a type of the anonymous namespace).
namespace merging {

/// Placed stations: their down-sampled world points and normals (oriented toward
/// their station).
struct Placed {
  PointList points;
  std::vector<Vec3> normals;
};

}  // namespace merging

namespace {

using merging::Placed;

/// The points (and normals) of every placed set inside box, in the sets' order.
void insideBox(const std::vector<const Placed*>& sets, const Aabb& box, PointList& out,
               std::vector<Vec3>& out_normals) {
  for (const Placed* set : sets) insideBox(set->points, set->normals, box, out, out_normals);
}

}  // namespace

namespace merging {

/// A voxel's key, point sum and count, all zero bytes when empty (a plain struct, so
/// the kernel's zero pages are empty slots).
struct Slot {
  std::uint64_t key;
  double sum[3];
  std::uint32_t count;  ///< 0: empty
};

/// Slots mapped straight from the kernel (mmap): zero-filled, untouched pages take no
/// memory, and a table that grows returns the old one to the system at once (on the
/// heap each growth left the old block behind as a hole: 1.4 GB at 200 stations
/// instead of 0.6 GB).
class SlotArray {
 public:
  SlotArray() = default;
  explicit SlotArray(std::size_t n) : n_(n) {
    if (n == 0) return;
    void* p = ::mmap(nullptr, bytes(), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    data_ = static_cast<Slot*>(p);
  }
  ~SlotArray() {
    if (data_ != nullptr) ::munmap(data_, bytes());
  }
  SlotArray(SlotArray&& o) noexcept { swap(o); }
  SlotArray& operator=(SlotArray&& o) noexcept {
    swap(o);
    return *this;
  }
  SlotArray(const SlotArray&) = delete;
  SlotArray& operator=(const SlotArray&) = delete;

  std::size_t size() const { return n_; }
  Slot& operator[](std::size_t i) { return data_[i]; }
  const Slot& operator[](std::size_t i) const { return data_[i]; }
  Slot* begin() { return data_; }
  /// Returns the whole pages past the first `keep` slots to the system (they read
  /// as zeros again).
  void releaseAfter(std::size_t keep) {
    const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
    const std::size_t from = (keep * sizeof(Slot) + page - 1) / page * page;
    if (data_ != nullptr && from < bytes())
      ::madvise(reinterpret_cast<char*>(data_) + from, bytes() - from, MADV_DONTNEED);
  }

 private:
  std::size_t bytes() const { return n_ * sizeof(Slot); }
  void swap(SlotArray& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(n_, o.n_);
  }
  Slot* data_{nullptr};
  std::size_t n_{0};
};

/// Centroid sums of the merged cloud's voxels (edge `leaf`), station by station, on
/// voxelDownsample's keys, so the centroids (sums in point order) and their key
/// order are voxelDownsample's on the concatenated stations. kTables open-addressing
/// tables chosen by the key's hash: each grows on its own, so a growth holds a small
/// part of the map twice, not all of it.
class VoxelSums {
 public:
  explicit VoxelSums(double leaf) : leaf_(leaf) {}

  /// Adds points (world frame) in order. Throws InputError like voxelDownsample when
  /// the points seen so far span more than 2^21 voxels on an axis, and before a
  /// table grows beyond the memory budget.
  void add(const PointList& points) {
    for (const auto& p : points) {
      const auto c = VoxelKeyer::latticeIndex(p, leaf_, kVoxelWhat);
      for (std::size_t a = 0; a < 3; ++a) {
        lo_[a] = any_ ? std::min(lo_[a], c[a]) : c[a];
        hi_[a] = any_ ? std::max(hi_[a], c[a]) : c[a];
      }
      any_ = true;
      const std::uint64_t key = VoxelKeyer::wrappedKey(c);
      const std::uint64_t hash = key * kGolden;
      Table& t = tables_[hash >> (64 - kTableBits)];
      if (20 * (t.used + 1) > 17 * t.slots.size()) grow(t);
      Slot& s = t.find(key, hash << kTableBits);
      if (s.count == 0) ++t.used;
      s.sum[0] += p.x();
      s.sum[1] += p.y();
      s.sum[2] += p.z();
      ++s.count;
    }
    if (any_) (void)VoxelKeyer::forIndexBox(lo_, hi_, leaf_, kVoxelWhat);  // throws beyond 2^21
  }

  std::size_t size() const {
    std::size_t n = 0;
    for (const Table& t : tables_) n += t.used;
    return n;
  }

  /// The centroids in key order; empties the map.
  PointList centroids() {
    for (Table& t : tables_) t.sortEntries();
    PointList out;
    out.reserve(size());
    // Every table's entries ascend by key: a merge of kTables runs.
    using Head = std::pair<std::uint64_t, std::size_t>;  // key, table
    std::priority_queue<Head, std::vector<Head>, std::greater<>> heads;
    std::array<std::size_t, kTables> next{};
    for (std::size_t i = 0; i < kTables; ++i)
      if (tables_[i].used > 0) heads.push({tables_[i].slots[0].key, i});
    while (!heads.empty()) {
      const std::size_t i = heads.top().second;
      heads.pop();
      const Slot& s = tables_[i].slots[next[i]++];
      out.push_back(Vec3(s.sum[0], s.sum[1], s.sum[2]) / static_cast<double>(s.count));
      if (next[i] < tables_[i].used) heads.push({tables_[i].slots[next[i]].key, i});
    }
    tables_ = {};
    slot_bytes_ = 0.0;
    return out;
  }

 private:
  /// One open-addressing table (linear probing; slots a power of two).
  struct Table {
    SlotArray slots;
    std::size_t used{0};
    int shift{64};
    /// The slot of key (empty if new); `spread` = the key's hash without the table bits.
    Slot& find(std::uint64_t key, std::uint64_t spread) {
      const std::size_t mask = slots.size() - 1;
      for (std::size_t i = spread >> shift;; i = (i + 1) & mask) {
        Slot& s = slots[i];
        if (s.count == 0) {
          s.key = key;
          return s;
        }
        if (s.key == key) return s;
      }
    }
    /// The used slots first, ascending by key; the rest given back to the system.
    void sortEntries() {
      std::size_t n = 0;
      for (std::size_t i = 0; i < slots.size(); ++i)
        if (slots[i].count > 0) slots[n++] = slots[i];
      slots.releaseAfter(n);
      std::sort(slots.begin(), slots.begin() + n,
                [](const Slot& a, const Slot& b) { return a.key < b.key; });
    }
  };
  static constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ULL;
  static constexpr int kTableBits = 6;
  static constexpr std::size_t kTables = std::size_t{1} << kTableBits;
  static constexpr const char* kVoxelWhat = "registration.downsample_m/output_voxel_m";

  void grow(Table& t) {
    const std::size_t capacity = t.slots.size() == 0 ? std::size_t{1} << 10 : 2 * t.slots.size();
    const double added = static_cast<double>(capacity * sizeof(Slot));
    requireMemory(slot_bytes_ + added,
                  "the merged cloud's " + std::to_string(size()) + "+ voxels of " +
                      formatNumber(leaf_) + " m",
                  "raise registration.output_voxel_m");
    SlotArray old(capacity);
    std::swap(old, t.slots);
    t.shift = 64 - static_cast<int>(std::log2(static_cast<double>(capacity)) + 0.5);
    for (std::size_t i = 0; i < old.size(); ++i)
      if (old[i].count > 0) t.find(old[i].key, (old[i].key * kGolden) << kTableBits) = old[i];
    slot_bytes_ += added - static_cast<double>(old.size() * sizeof(Slot));
  }

  double leaf_;
  std::array<Table, kTables> tables_;
  double slot_bytes_{0.0};  ///< memory of every table's slots [bytes]
  bool any_{false};
  std::array<std::int64_t, 3> lo_{}, hi_{};
};

}  // namespace merging

struct StationMerger::State {
  explicit State(const RegistrationOptions& o) : options(o), sums(o.output_voxel_m) {}
  RegistrationOptions options;
  bool have_reference{false};
  Aabb placed_box;            ///< of every placed point
  std::deque<Placed> recent;  ///< the last recent_stations placed stations
  Placed older;               ///< the first point per downsample_m voxel of the others
  std::unordered_set<std::uint64_t> older_keys;
  merging::VoxelSums sums;  ///< output_voxel_m > 0
  PointList all;            ///< output_voxel_m = 0: every point

  /// The placed sets in placement order: the older stations, then the recent ones.
  std::vector<const Placed*> placed() const {
    std::vector<const Placed*> out;
    if (!older.points.empty()) out.push_back(&older);
    for (const Placed& p : recent) out.push_back(&p);
    return out;
  }

  /// Adds a placed station; the one that leaves the recent window joins `older`.
  void place(Placed station) {
    for (const auto& p : station.points) placed_box.extend(p);
    recent.push_back(std::move(station));
    if (recent.size() <= static_cast<std::size_t>(options.recent_stations)) return;
    const Placed& leaving = recent.front();
    for (std::size_t i = 0; i < leaving.points.size(); ++i) {
      const auto c = VoxelKeyer::latticeIndex(leaving.points[i], options.downsample_m);
      if (!older_keys.insert(VoxelKeyer::wrappedKey(c)).second) continue;
      older.points.push_back(leaving.points[i]);
      older.normals.push_back(leaving.normals[i]);
    }
    recent.pop_front();
  }
};

StationMerger::StationMerger(const RegistrationOptions& options)
    : state_(std::make_unique<State>(options)) {
  options.validate();
}

StationMerger::~StationMerger() = default;

PreparedStation StationMerger::prepare(const StationInput& in) const {
  const auto t0 = SteadyClock::now();
  PreparedStation p;
  if (in.points.empty()) return p;
  p.downsampled = voxelDownsample(in.points, state_->options.downsample_m, 1);
  // In the station frame, oriented toward the station (its origin).
  p.normals = normalsOf(p.downsampled, Vec3::Zero(), state_->options.normal_k);
  p.seconds = secondsSince(t0);
  return p;
}

namespace {

/// Registers the overlap (predicted from the initial poses) of guess onto the placed
/// stations (`placed`, whose points span `placed_box`) into r; on convergence moves
/// guess and normals by the correction.
void registerOverlap(const StationInput& in, const PointList& ds,
                     const std::vector<const Placed*>& placed, const Aabb& placed_box,
                     const RegistrationOptions& options, PointList& guess,
                     std::vector<Vec3>& normals, StationResult& r) {
  PointList src, tgt;
  std::vector<Vec3> src_n, tgt_n;
  insideBox(guess, normals, grown(placed_box, options.overlap_margin_m), src, src_n);
  insideBox(placed, grown(boundingBox(guess), options.overlap_margin_m), tgt, tgt_n);
  r.overlap_points = src.size();
  const Alignment a = align(src, src_n, tgt, tgt_n, options);
  r.converged = a.converged;
  r.fitness_rms_m = a.rms;
  r.iterations = a.iterations;
  r.pairs = a.pairs;
  r.information = a.information;
  r.weakest_direction = a.directions.col(0);
  if (a.converged) {
    r.pose = a.delta * in.initial_pose;
    guess = transformed(ds, r.pose);
    for (auto& n : normals) n = a.delta.linear() * n;
  }
}

}  // namespace

StationResult StationMerger::add(const StationInput& in, PreparedStation prepared) {
  State& s = *state_;
  const auto ts = SteadyClock::now();
  StationResult r;
  r.id = in.id;
  r.initial_pose = in.initial_pose;
  r.pose = in.initial_pose;
  r.points = in.points.size();
  if (in.points.empty()) return r;
  const PointList& ds = prepared.downsampled;
  Placed station{transformed(ds, in.initial_pose), std::move(prepared.normals)};
  for (auto& n : station.normals) n = in.initial_pose.linear() * n;  // rotated with the points
  if (!s.have_reference || s.options.method == Method::None) {
    r.converged = true;
  } else {
    registerOverlap(in, ds, s.placed(), s.placed_box, s.options, station.points, station.normals,
                    r);
  }
  s.have_reference = true;
  s.place(std::move(station));
  // The full cloud at its registered pose, into the merged cloud.
  PointList moved(in.points.size());
  parallelFor((moved.size() + (1 << 16) - 1) >> 16, s.options.threads,
              [&](std::size_t b, std::size_t) {
                const std::size_t end = std::min(moved.size(), (b + 1) << 16);
                for (std::size_t k = b << 16; k < end; ++k) moved[k] = r.pose * in.points[k];
              });
  if (s.options.output_voxel_m > 0.0)
    s.sums.add(moved);
  else
    s.all.insert(s.all.end(), moved.begin(), moved.end());
  r.time_s = prepared.seconds + secondsSince(ts);
  return r;
}

std::size_t StationMerger::mergedSize() const {
  return state_->options.output_voxel_m > 0.0 ? state_->sums.size() : state_->all.size();
}

PointList StationMerger::finish() {
  State& s = *state_;
  if (!s.have_reference) throw InputError(kNothingToRegister);
  PointList out = s.options.output_voxel_m > 0.0 ? s.sums.centroids() : std::move(s.all);
  state_ = std::make_unique<State>(s.options);
  return out;
}

RegistrationResult registerStations(const std::vector<StationInput>& stations,
                                    const RegistrationOptions& options) {
  options.validate();
  const auto t0 = SteadyClock::now();
  (void)referenceStation(stations);
  StationMerger merger(options);
  // Down-sampling and normals do not depend on the order: every station's at once.
  std::vector<PreparedStation> prepared(stations.size());
  parallelFor(stations.size(), options.threads,
              [&](std::size_t i, std::size_t) { prepared[i] = merger.prepare(stations[i]); });
  RegistrationResult result;
  for (std::size_t i = 0; i < stations.size(); ++i)
    result.stations.push_back(merger.add(stations[i], std::move(prepared[i])));
  result.merged = merger.finish();
  result.time_s = secondsSince(t0);
  return result;
}

}  // namespace uavip::registration
