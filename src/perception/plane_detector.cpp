#include "uavip/perception/plane_detector.h"

#include <pcl/ModelCoefficients.h>
#include <pcl/PointIndices.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/ransac.h>
#include <pcl/sample_consensus/sac_model_plane.h>
#include <pcl/surface/convex_hull.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <future>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <random>
#include <sstream>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/math.h"
#include "uavip/core/parallel.h"
#include "uavip/core/pcl_cloud.h"
#include "uavip/core/voxel_key.h"
#include "uavip/perception/euclidean_clusters.h"
#include "uavip/perception/surface_outline.h"

namespace uavip::perception {
namespace {

using PclCloud = pcl::PointCloud<pcl::PointXYZ>;
using Index = pcl::index_t;

/// Second / largest covariance eigenvalue below which a point set is a line
/// (numerical, not tuning: PlaneTuning holds those).
constexpr double kDegenerateRatio = 1e-10;

/// Principal component analysis of cloud[idx] (in double precision).
struct Pca {
  Vec3 centroid{Vec3::Zero()};
  Vec3 eigenvalues{Vec3::Zero()};  ///< ascending
  Vec3 normal{Vec3::UnitZ()};      ///< smallest-variance direction
  Vec3 major{Vec3::UnitX()};       ///< largest-variance direction, sign made deterministic
};

Pca computePca(const PointList& cloud, const std::vector<Index>& idx) {
  Pca pca;
  if (idx.empty()) return pca;
  for (const auto i : idx) pca.centroid += cloud[static_cast<std::size_t>(i)];
  pca.centroid /= static_cast<double>(idx.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto i : idx) {
    const Vec3 d = cloud[static_cast<std::size_t>(i)] - pca.centroid;
    cov += d * d.transpose();
  }
  cov /= static_cast<double>(idx.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
  pca.eigenvalues = solver.eigenvalues();
  pca.normal = solver.eigenvectors().col(0).normalized();
  pca.major = solver.eigenvectors().col(2).normalized();
  // Deterministic sign: the largest component of the major axis is positive.
  Eigen::Index k = 0;
  pca.major.cwiseAbs().maxCoeff(&k);
  if (pca.major[k] < 0.0) pca.major = -pca.major;
  return pca;
}

bool isDegenerate(const Pca& pca) {
  const double largest = pca.eigenvalues[2];
  return !(largest > 0.0) || pca.eigenvalues[1] <= kDegenerateRatio * largest;
}

/// Tightens the RANSAC inliers `candidate` to the points within a robust band
/// (median ± band_sigmas · 1.4826 · MAD of the plane distances, between
/// band_floor × threshold and threshold) around their plane. Not inlined: inlined into
/// detectPlanes, GCC 12 reports a false -Wfree-nonheap-object on its vectors.
[[gnu::noinline]] std::vector<Index> refineBand(const PointList& cloud,
                                                const std::vector<Index>& candidate,
                                                double threshold, const PlaneTuning& tuning) {
  std::vector<Index> current = candidate;
  for (int iter = 0; iter < tuning.band_iterations && current.size() >= 3; ++iter) {
    const Pca pca = computePca(cloud, current);
    std::vector<double> dist(candidate.size());
    for (std::size_t j = 0; j < candidate.size(); ++j) {
      dist[j] = pca.normal.dot(cloud[static_cast<std::size_t>(candidate[j])] - pca.centroid);
    }
    const double med = upperMedian(dist);
    std::vector<double> dev(dist.size());
    for (std::size_t j = 0; j < dist.size(); ++j) dev[j] = std::abs(dist[j] - med);
    const double sigma = 1.4826 * upperMedian(dev);
    const double band =
        std::clamp(tuning.band_sigmas * sigma, tuning.band_floor * threshold, threshold);
    std::vector<Index> next;
    next.reserve(candidate.size());
    for (std::size_t j = 0; j < candidate.size(); ++j) {
      if (dev[j] <= band) next.push_back(candidate[j]);
    }
    if (next == current) break;
    current = std::move(next);
  }
  return current;
}

/// The largest Euclidean cluster of cloud[idx] (euclidean_clusters.h); ties: the
/// cluster holding the smallest index. Sorted ascending.
std::vector<Index> largestCluster(const PointList& cloud, const std::vector<Index>& idx,
                                  double tolerance) {
  if (idx.size() <= 1) return idx;
  const std::vector<std::vector<int>> clusters = euclideanClusters(cloud, idx, tolerance);
  const std::vector<int>* best = nullptr;
  for (const auto& c : clusters) {  // ordered by smallest index: the first of equal size wins
    if (best == nullptr || c.size() > best->size()) best = &c;
  }
  return best ? *best : std::vector<Index>{};
}

/// 2D convex hull (PCL ConvexHull, dimension 2) of planar coordinates, as (u, v)
/// pairs counter-clockwise. Empty when the points span no area. Kept apart from
/// core's convexHull2d on purpose: its vertices are float-rounded, start where qhull's
/// angular sort about their centroid starts, and qhull merges nearly collinear ones;
/// all three reach scene.json, so core's exact chain would change outputs.
std::vector<Eigen::Vector2d> qhullBoundary2d(const std::vector<Eigen::Vector2d>& uv) {
  if (uv.size() < 3) return {};
  // Degenerate (collinear) sets make qhull fail noisily: detect them first.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : uv) mean += p;
  mean /= static_cast<double>(uv.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& p : uv) cov += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(cov);
  if (!(solver.eigenvalues()[1] > 0.0) ||
      solver.eigenvalues()[0] <= kDegenerateRatio * solver.eigenvalues()[1]) {
    return {};
  }

  auto cloud = std::make_shared<PclCloud>();
  cloud->points.reserve(uv.size());
  for (const auto& p : uv) {
    cloud->points.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.0F);
  }
  cloud->width = static_cast<std::uint32_t>(cloud->points.size());
  cloud->height = 1;
  pcl::ConvexHull<pcl::PointXYZ> hull;
  hull.setInputCloud(cloud);
  hull.setDimension(2);
  PclCloud hull_points;
  hull.reconstruct(hull_points);
  if (hull_points.size() < 3) return {};

  std::vector<Eigen::Vector2d> out;
  out.reserve(hull_points.size());
  for (const auto& p : hull_points.points) out.emplace_back(p.x, p.y);
  if (polygonTwiceSignedArea2d(out) < 0.0) std::reverse(out.begin(), out.end());
  return out;
}

/// Occupied voxels of a point set (sorted 64-bit keys), for line-of-sight tests.
class OccupiedVoxels {
 public:
  OccupiedVoxels(const PointList& cloud, double edge)
      : box_(boundingBox(cloud)),
        keyer_(box_.min - Vec3::Constant(edge), box_.max + Vec3::Constant(edge), edge,
               "line-of-sight voxel"),
        keys_(occupiedKeys(cloud, keyer_)) {
    for (const auto& p : cloud) centroid_ += p;
    centroid_ /= static_cast<double>(std::max<std::size_t>(cloud.size(), 1));
  }
  std::uint64_t key(const Vec3& p) const { return keyer_.key(p); }
  bool occupied(std::uint64_t k) const { return std::binary_search(keys_.begin(), keys_.end(), k); }
  double edge() const { return keyer_.edge(); }
  /// True once p has left the cloud's bounding box by more than one voxel.
  bool outside(const Vec3& p) const {
    return ((p - box_.min).array() < -edge()).any() || ((p - box_.max).array() > edge()).any();
  }
  const Vec3& centroid() const { return centroid_; }
  /// True if p lies below the cloud's bottom (a ray that leaves there went underground).
  bool below(const Vec3& p) const { return p.z() < box_.min.z() - edge(); }

 private:
  Aabb box_;
  VoxelKeyer keyer_;
  std::vector<std::uint64_t> keys_;
  Vec3 centroid_{Vec3::Zero()};
};

/// Keys of the voxels holding cloud[kept], sorted (a surface's own voxels never
/// block the rays that start on it).
std::vector<std::uint64_t> ownKeys(const PointList& cloud, const std::vector<Index>& kept,
                                   const OccupiedVoxels& occupied) {
  std::vector<std::uint64_t> own;
  own.reserve(kept.size());
  for (const auto i : kept) own.push_back(occupied.key(cloud[static_cast<std::size_t>(i)]));
  std::sort(own.begin(), own.end());
  own.erase(std::unique(own.begin(), own.end()), own.end());
  return own;
}

/// Openness for a cloud without a known sensor position (a file from airborne or
/// mobile LiDAR, a model): +1 / −1 toward the side of the plane from which more rays
/// leave the cloud's bounds (through its top or sides: below the lowest point is
/// ground) without crossing a voxel occupied by another part of the cloud — the
/// outside of a building, the sky above a roof; 0 when the two sides
/// differ by less than open_margin (a lone wall, the ground with nothing below).
/// Rays start at up to open_samples inliers, along ±n and 30° off it toward ±u, ±v.
double opennessSide(const PointList& cloud, const std::vector<Index>& kept, const Vec3& n,
                    const Vec3& u, const Vec3& v, const OccupiedVoxels& occupied,
                    const PlaneTuning& tuning) {
  const std::vector<std::uint64_t> own = ownKeys(cloud, kept, occupied);
  const double step = 0.5 * occupied.edge();
  const std::size_t samples = std::min(static_cast<std::size_t>(tuning.open_samples), kept.size());
  const double c = 0.8660254037844386, s = 0.5;  // cos, sin of 30°
  int open[2] = {0, 0};
  int cast = 0;
  for (std::size_t r = 0; r < samples; ++r) {
    const Vec3& start = cloud[static_cast<std::size_t>(kept[r * kept.size() / samples])];
    for (int side = 0; side < 2; ++side) {
      const Vec3 ns = side == 0 ? n : Vec3(-n);
      const Vec3 dirs[5] = {ns, c * ns + s * u, c * ns - s * u, c * ns + s * v, c * ns - s * v};
      for (const auto& d : dirs) {
        cast += side == 0;
        Vec3 p = start + d * occupied.edge();
        bool blocked = false;
        while (!occupied.outside(p)) {
          const std::uint64_t k = occupied.key(p);
          if (occupied.occupied(k) && !std::binary_search(own.begin(), own.end(), k)) {
            blocked = true;
            break;
          }
          p += d * step;
        }
        // Leaving through the bottom of the cloud is not "open": nothing was
        // measured under the ground because it is solid, not free.
        if (!blocked && !occupied.below(p)) ++open[side];
      }
    }
  }
  if (cast == 0) return 0.0;
  const double f = static_cast<double>(open[0]) / cast;
  const double b = static_cast<double>(open[1]) / cast;
  if (std::abs(f - b) < tuning.open_margin) return 0.0;
  return f > b ? 1.0 : -1.0;
}

/// Line of sight for scanned clouds: +1 / −1 toward the side of the plane (n through
/// centroid) from which a larger share (≥ half) of the (viewpoint, inlier) rays
/// reach the surface without crossing a voxel occupied by another part of the
/// cloud, 0 if neither side does. Voxels
/// holding the surface's own inliers do not block (a grazing ray runs along them),
/// and a ray ends sight_stop_m before its target; rays longer than sight_range_m
/// are not cast. From behind a closed object a ray crosses the object's other faces
/// and is blocked.
double sightSide(const PointList& cloud, const std::vector<Index>& kept, const Vec3& centroid,
                 const Vec3& n, const std::vector<Vec3>& viewpoints, const OccupiedVoxels& occupied,
                 const PlaneTuning& tuning) {
  const double stop = tuning.sight_stop_m;
  const std::vector<std::uint64_t> own = ownKeys(cloud, kept, occupied);
  const double step = 0.5 * occupied.edge();
  const std::size_t rays = std::min(static_cast<std::size_t>(tuning.sight_rays), kept.size());
  int front = 0, back = 0, front_cast = 0, back_cast = 0;
  for (const auto& vp : viewpoints) {
    const double side = n.dot(vp - centroid);
    if (std::abs(side) < 1e-6) continue;  // in the plane: sees neither face
    for (std::size_t r = 0; r < rays; ++r) {
      const Vec3& target = cloud[static_cast<std::size_t>(kept[r * kept.size() / rays])];
      const Vec3 d = target - vp;
      const double length = d.norm();
      if (length > tuning.sight_range_m || length <= stop) continue;
      (side > 0.0 ? front_cast : back_cast) += 1;
      bool clear = true;
      for (double t = 0.0; t < length - stop && clear; t += step) {
        const std::uint64_t k = occupied.key(vp + d * (t / length));
        clear = !occupied.occupied(k) || std::binary_search(own.begin(), own.end(), k);
      }
      if (clear) (side > 0.0 ? front : back) += 1;
    }
  }
  // A side counts when most of its rays get through: from behind a closed object
  // only the rays to the face's rim (shared with the faces in front) do.
  const double f = front_cast ? static_cast<double>(front) / front_cast : 0.0;
  const double b = back_cast ? static_cast<double>(back) / back_cast : 0.0;
  if (std::max(f, b) < tuning.sight_fraction || f == b) return 0.0;
  return f > b ? 1.0 : -1.0;
}

/// Sign (+1 / -1) that turns `n` toward free space. For a scanned cloud (occupied
/// given) the side the stations see it from decides (sightSide). Otherwise, or
/// when no station sees it: the surface's extent (lo..hi in
/// (u, v)) is cut into orient_cell_m cells; a cell that holds inliers is "enclosed"
/// on a side when the column in front of it on that side, from orient_near_m to
/// orient_depth_m, holds a cloud point. A side enclosed over ≥ enclosed_fraction of the
/// cells is the inside of a closed object (a cube face, a pier face, a deck edge):
/// the normal points to the other side. When neither or both sides are enclosed
/// (a lone wall, the ground under a bridge, the underside of a deck), the sensor
/// nearest viewpoint decides, as PCL's flipNormalTowardsViewpoint does. Counting points per
/// side instead would turn the ground under a pier upside down.
double orientation(const PointList& cloud, const std::vector<Index>& kept, const Vec3& centroid,
                   const Vec3& n, const Vec3& u, const Vec3& v, const Eigen::Vector2d& lo,
                   const Eigen::Vector2d& hi, const PlaneDetectionOptions& options,
                   const OccupiedVoxels* occupied) {
  if (options.single_station) {
    const double sv = n.dot(options.viewpoint - centroid);
    if (std::abs(sv) > 1e-9) return sv > 0.0 ? 1.0 : -1.0;
  }
  if (occupied && !options.viewpoint_known) {
    const double open = opennessSide(cloud, kept, n, u, v, *occupied, options.tuning);
    if (open != 0.0) return open;
  }
  if (occupied && options.viewpoints_scanned) {
    std::vector<Vec3> viewpoints = options.extra_viewpoints;
    viewpoints.push_back(options.viewpoint);
    const double sight = sightSide(cloud, kept, centroid, n, viewpoints, *occupied, options.tuning);
    if (sight != 0.0) return sight;
  }
  const PlaneTuning& t = options.tuning;
  const double cell = t.orient_cell_m;
  const int nu = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / cell)));
  const int nv = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / cell)));
  const auto cellOf = [&](double pu, double pv) {
    const int i = std::clamp(static_cast<int>((pu - lo.x()) / cell), 0, nu - 1);
    const int j = std::clamp(static_cast<int>((pv - lo.y()) / cell), 0, nv - 1);
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(nu) + static_cast<std::size_t>(i);
  };
  const std::size_t cells = static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv);
  // bit 0: the cell holds inliers, bit 1: enclosed in front, bit 2: enclosed behind
  std::vector<std::uint8_t> state(cells, 0);
  for (const auto i : kept) {
    const Vec3 d = cloud[static_cast<std::size_t>(i)] - centroid;
    state[cellOf(u.dot(d), v.dot(d))] |= 1;
  }
  for (const auto& p : cloud) {
    const Vec3 d = p - centroid;
    const double s = n.dot(d);
    if (std::abs(s) <= t.orient_near_m || std::abs(s) > t.orient_depth_m) continue;
    const double pu = u.dot(d);
    const double pv = v.dot(d);
    if (pu < lo.x() || pu > hi.x() || pv < lo.y() || pv > hi.y()) continue;
    state[cellOf(pu, pv)] |= s > 0.0 ? 2 : 4;
  }
  std::size_t surface_cells = 0, front = 0, back = 0;
  for (const auto c : state) {
    if (!(c & 1)) continue;
    ++surface_cells;
    front += (c & 2) != 0;
    back += (c & 4) != 0;
  }
  const double limit = t.enclosed_fraction * static_cast<double>(surface_cells);
  const bool front_enclosed = static_cast<double>(front) >= limit;
  const bool back_enclosed = static_cast<double>(back) >= limit;
  if (front_enclosed != back_enclosed) return front_enclosed ? -1.0 : 1.0;
  if (!options.viewpoint_known) {
    // No sensor position: level-ish surfaces face up (ground, roofs, decks seen from
    // the air); walls face away from the middle of the cloud.
    if (std::abs(n.z()) > 0.3) return n.z() > 0.0 ? 1.0 : -1.0;
    if (occupied) return n.dot(centroid - occupied->centroid()) >= 0.0 ? 1.0 : -1.0;
  }
  Vec3 viewpoint = options.viewpoint;
  for (const auto& vp : options.extra_viewpoints) {
    if ((vp - centroid).squaredNorm() < (viewpoint - centroid).squaredNorm()) viewpoint = vp;
  }
  const double sv = n.dot(viewpoint - centroid);
  if (std::abs(sv) > 1e-9) return sv > 0.0 ? 1.0 : -1.0;
  constexpr double kEps = 1e-9;
  if (std::abs(n.z()) > kEps) return n.z() > 0.0 ? 1.0 : -1.0;
  if (std::abs(n.x()) > kEps) return n.x() > 0.0 ? 1.0 : -1.0;
  return n.y() >= 0.0 ? 1.0 : -1.0;
}

/// Area the planar points occupy: distinct cells of edge `cell` [m] × cell² [m²]
/// (not count × cell²: a tilted plane through a voxel grid holds more points per m²).
double occupiedArea(const std::vector<Eigen::Vector2d>& uv, double cell) {
  if (uv.empty()) return 0.0;
  static const PlaneDetectionOptions defaults;
  static const std::string& key =
      PlaneDetectionOptions::table().find(defaults, &defaults.cell_size_m)->key;
  PointList flat;  // the (u, v) coordinates as points of the plane z = 0
  flat.reserve(uv.size());
  for (const auto& q : uv) flat.emplace_back(q.x(), q.y(), 0.0);
  const auto cells =
      static_cast<double>(occupiedKeys(flat, VoxelKeyer::forPoints(flat, cell, key)).size());
  return cells * cell * cell;
}

/// The boundary of `s` from its inliers' plane coordinates `uv` (options.boundary):
/// the outline of the occupied cells with its holes, or the paper's convex hull;
/// and the area it encloses.
void setBoundary(Surface& s, const std::vector<Eigen::Vector2d>& uv,
                 const PlaneDetectionOptions& options) {
  const auto to3d = [&](const std::vector<Eigen::Vector2d>& loop) {
    PointList out;
    out.reserve(loop.size());
    for (const auto& q : loop) out.push_back(s.centroid + q.x() * s.axis_u + q.y() * s.axis_v);
    return out;
  };
  if (options.boundary == "convex") {
    s.boundary = to3d(qhullBoundary2d(uv));
    s.area_m2 = polygonArea(s.boundary);
    return;
  }
  const Outline2d o = occupiedOutline2d(uv, options.outlineOptions());
  s.boundary = to3d(o.outer);
  for (const auto& h : o.holes) s.holes.push_back(to3d(h));
  s.area_m2 = o.area_m2;
}

/// Builds the surface of the kept inliers: PCA plane, oriented normal, axes,
/// boundary (setBoundary) and both areas.
Surface makeSurface(const PointList& cloud, const std::vector<Index>& kept,
                    const PlaneDetectionOptions& options, const OccupiedVoxels* occupied) {
  const Pca pca = computePca(cloud, kept);
  Surface s;
  s.centroid = pca.centroid;
  const Vec3 n0 = pca.normal;
  const Vec3 u = (pca.major - pca.major.dot(n0) * n0).normalized();
  const Vec3 v0 = n0.cross(u);

  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const auto i : kept) {
    const Vec3 d = cloud[static_cast<std::size_t>(i)] - s.centroid;
    const Eigen::Vector2d q(u.dot(d), v0.dot(d));
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  const double sign = orientation(cloud, kept, s.centroid, n0, u, v0, lo, hi, options, occupied);
  s.plane.normal = sign * n0;
  s.plane.offset = -s.plane.normal.dot(s.centroid);
  s.axis_u = u;
  s.axis_v = s.plane.normal.cross(u);

  s.inliers.reserve(kept.size());
  std::vector<Eigen::Vector2d> uv;
  uv.reserve(kept.size());
  for (const auto i : kept) {
    const Vec3& p = cloud[static_cast<std::size_t>(i)];
    s.inliers.push_back(p);
    const Vec3 d = p - s.centroid;
    uv.emplace_back(s.axis_u.dot(d), s.axis_v.dot(d));
  }
  setBoundary(s, uv, options);
  s.density_area_m2 = occupiedArea(uv, options.cell_size_m);
  return s;
}

/// Removes the sorted indices `drop` from the sorted `pool`.
void removeFromPool(std::vector<Index>& pool, const std::vector<Index>& drop) {
  std::vector<Index> out;
  out.reserve(pool.size());
  std::set_difference(pool.begin(), pool.end(), drop.begin(), drop.end(), std::back_inserter(out));
  pool = std::move(out);
}

/// The largest float strictly below t: for any float f, f < t (in double) exactly
/// when f ≤ largestFloatBelow(t).
float largestFloatBelow(double t) {
  float g = static_cast<float>(t);
  if (static_cast<double>(g) >= t) g = std::nextafter(g, -std::numeric_limits<float>::infinity());
  return g;
}

/// PCL's plane model whose hypothesis count (the inner loop of RANSAC) runs over
/// the indexed points copied into contiguous arrays. PCL 1.13's generic count reads
/// each point through the index and a dynamic-size Eigen dot product: about 10 ns a
/// point on the development machine, against about 0.3 ns here (benchmarks/README.md,
/// "Detection"); sampling, the adaptive iteration count, the least-squares refinement
/// and the inlier selection stay PCL's. The count selects the same points as PCL's
/// test |n·p + d| < threshold (float distance, double threshold), compared in float
/// against largestFloatBelow(threshold) so that it vectorises.
class ContiguousPlaneModel final : public pcl::SampleConsensusModelPlane<pcl::PointXYZ> {
 public:
  ContiguousPlaneModel(const PclCloud::ConstPtr& cloud, const pcl::Indices& indices)
      : pcl::SampleConsensusModelPlane<pcl::PointXYZ>(cloud, indices, false) {
    x_.reserve(indices.size());
    y_.reserve(indices.size());
    z_.reserve(indices.size());
    for (const auto i : indices) {
      const pcl::PointXYZ& p = (*cloud)[static_cast<std::size_t>(i)];
      x_.push_back(p.x);
      y_.push_back(p.y);
      z_.push_back(p.z);
    }
  }

  std::size_t countWithinDistance(const Eigen::VectorXf& c, const double threshold) const override {
    if (!isModelValid(c)) return 0;
    const float a = c[0], b = c[1], e = c[2], d = c[3];
    const float below = largestFloatBelow(threshold);
    // |·| < threshold in double is |·| ≤ below in float: the same points, and a loop
    // the compiler runs four floats at a time.
    std::uint32_t n = 0;
    const std::size_t size = x_.size();
    const float* x = x_.data();
    const float* y = y_.data();
    const float* z = z_.data();
    for (std::size_t k = 0; k < size; ++k)
      n += std::abs(a * x[k] + b * y[k] + e * z[k] + d) <= below ? 1u : 0u;
    return n;
  }

 private:
  std::vector<float> x_, y_, z_;
};

/// The line-of-sight grid: for scanned clouds (tuning.sight_voxel_m), and for clouds
/// with no known sensor position (openness, open_voxel_m); none when the viewpoint is
/// known.
std::unique_ptr<OccupiedVoxels> lineOfSightVoxels(const PointList& cloud,
                                                  const PlaneDetectionOptions& options) {
  if (options.viewpoints_scanned)
    return std::make_unique<OccupiedVoxels>(cloud, options.tuning.sight_voxel_m);
  if (!options.viewpoint_known)
    return std::make_unique<OccupiedVoxels>(cloud, options.open_voxel_m);
  return nullptr;
}

/// One RANSAC candidate (paper §II-D: threshold, iterations): PCL's RANSAC plane
/// (ContiguousPlaneModel, probability 0.99, serial: the result must not depend on
/// scheduling) scored on a random subset of the pool (at most `scoring_points`; the
/// inlier fraction of every plane is the same in expectation), refined by least
/// squares as pcl::SACSegmentation does, then every pool point within the threshold
/// of it (world frame). Empty when RANSAC finds nothing. PCL seeds its sampler with a
/// constant for every model; shuffling the pool with our seeded generator makes `seed`
/// select the samples.
std::vector<Index> ransacCandidate(const PclCloud::ConstPtr& pcl_cloud, const PointList& cloud,
                                   const std::vector<Index>& pool, const Vec3& origin,
                                   const PlaneDetectionOptions& options, std::mt19937& rng) {
  pcl::Indices shuffled(pool.begin(), pool.end());
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  if (shuffled.size() > options.tuning.ransac_scoring_points)
    shuffled.resize(options.tuning.ransac_scoring_points);
  const double threshold_m = options.distance_threshold_m;
  const auto model = std::make_shared<ContiguousPlaneModel>(pcl_cloud, shuffled);
  pcl::RandomSampleConsensus<pcl::PointXYZ> ransac(model, threshold_m);
  ransac.setMaxIterations(options.max_iterations);
  ransac.setProbability(0.99);
  ransac.setNumberOfThreads(-1);
  pcl::Indices ransac_inliers;
  Eigen::VectorXf coarse(4), refined(4);
  if (!ransac.computeModel(0)) return {};
  ransac.getInliers(ransac_inliers);
  ransac.getModelCoefficients(coarse);
  if (ransac_inliers.size() < 3 || coarse.size() != 4) return {};
  model->optimizeModelCoefficients(ransac_inliers, coarse, refined);
  model->selectWithinDistance(refined, threshold_m, ransac_inliers);
  if (ransac_inliers.size() < 3) return {};

  Vec3 n(refined[0], refined[1], refined[2]);
  double d = refined[3];
  const double norm = n.norm();
  std::vector<Index> candidate;
  if (norm > 0.0 && std::isfinite(norm)) {
    n /= norm;
    d = d / norm - n.dot(origin);
    for (const auto i : pool) {
      if (std::abs(n.dot(cloud[static_cast<std::size_t>(i)]) + d) <= threshold_m)
        candidate.push_back(i);
    }
  }
  if (candidate.size() < 3) {
    candidate.assign(ransac_inliers.begin(), ransac_inliers.end());
    std::sort(candidate.begin(), candidate.end());
  }
  return candidate;
}

/// One step of the sequential RANSAC on `pool`: its candidate plane, the refined
/// band and the band's largest cluster (the surface it may become); `stop` when the
/// pool is used up (its points span no plane, or RANSAC finds none).
struct CandidateStep {
  bool stop{false};
  std::vector<Index> candidate, band, kept;
};

/// What every step of one detection reads: the cloud (and its PCL copy about
/// `origin`) and the line-of-sight voxels.
struct DetectionContext {
  const PclCloud::ConstPtr& pcl_cloud;
  const PointList& cloud;
  const Vec3& origin;
  const OccupiedVoxels* occupied;
};

CandidateStep nextCandidate(const DetectionContext& c, const std::vector<Index>& pool,
                            const PlaneDetectionOptions& options, std::mt19937& rng) {
  CandidateStep step;
  if (isDegenerate(computePca(c.cloud, pool))) {  // a line or a single spot
    step.stop = true;
    return step;
  }
  step.candidate = ransacCandidate(c.pcl_cloud, c.cloud, pool, c.origin, options, rng);
  if (step.candidate.empty()) {
    step.stop = true;
    return step;
  }
  step.band = refineBand(c.cloud, step.candidate, options.distance_threshold_m, options.tuning);
  step.kept = largestCluster(c.cloud, step.band, options.cluster_tolerance_m);
  return step;
}

/// The surface of step.kept when stage 4 accepts it (its area and boundary), else
/// nothing. Sequential RANSAC depends on a step only through the pool and the
/// generator, so with `guess_next` the next step is taken meanwhile on a second
/// thread, on the pool as it will be if the surface is accepted and with a copy of
/// the generator; `next` gets it (and `rng` the copy) only when the surface is
/// accepted, else the guess is dropped: the surfaces are the one-thread ones.
std::optional<Surface> judgeCandidate(const CandidateStep& step, const std::vector<Index>& pool,
                                      bool guess_next, const DetectionContext& c,
                                      const PlaneDetectionOptions& options, std::mt19937& rng,
                                      std::optional<CandidateStep>& next) {
  std::vector<Index> pool_if_accepted;  // only when guessing
  if (guess_next) {
    pool_if_accepted = pool;
    removeFromPool(pool_if_accepted, step.kept);
  }
  std::mt19937 rng_if_accepted = rng;
  std::future<CandidateStep> guess;  // declared after what it reads: joined first
  if (pool_if_accepted.size() >= 3) {
    guess = std::async(std::launch::async, [&] {
      return nextCandidate(c, pool_if_accepted, options, rng_if_accepted);
    });
  }
  Surface surface = makeSurface(c.cloud, step.kept, options, c.occupied);
  const bool accepted = std::min(surface.area_m2, surface.density_area_m2) >= options.min_area_m2 &&
                        surface.boundary.size() >= 3;
  if (guess.valid() && accepted) {
    next = guess.get();
    rng = rng_if_accepted;
  } else if (guess.valid()) {
    guess.wait();  // a discarded guess: its result (or exception) is dropped
  }
  if (!accepted) return std::nullopt;
  return surface;
}

}  // namespace

void PlaneTuning::validate(const std::string& where) const {
  const auto fraction = [&](double v, const char* name) {
    requireThat(v >= 0.0 && v <= 1.0, where, name, "in [0, 1]", v);
  };
  const auto atLeastOne = [&](double v, const char* name) {
    requireThat(v >= 1.0, where, name, ">= 1", v);
  };
  const auto nonNegative = [&](double v, const char* name) {
    requireThat(std::isfinite(v) && v >= 0.0, where, name, ">= 0", v);
  };
  requirePositive(band_sigmas, where, "band_sigmas");
  fraction(band_floor, "band_floor");
  atLeastOne(band_iterations, "band_iterations");
  requireThat(ransac_scoring_points >= 3, where, "ransac_scoring_points", ">= 3",
              static_cast<double>(ransac_scoring_points));
  nonNegative(orient_near_m, "orient_near_m");
  requirePositive(orient_depth_m, where, "orient_depth_m");
  requirePositive(orient_cell_m, where, "orient_cell_m");
  fraction(enclosed_fraction, "enclosed_fraction");
  requirePositive(sight_voxel_m, where, "sight_voxel_m");
  requirePositive(sight_range_m, where, "sight_range_m");
  nonNegative(sight_stop_m, "sight_stop_m");
  atLeastOne(sight_rays, "sight_rays");
  fraction(sight_fraction, "sight_fraction");
  atLeastOne(open_samples, "open_samples");
  fraction(open_margin, "open_margin");
  requireThat(outline_cell_fraction > 0.0 && outline_cell_fraction <= 1.0, where,
              "outline_cell_fraction", "in (0, 1]", outline_cell_fraction);
  requireThat(outline_close_cells >= 0 && outline_close_cells <= 64, where, "outline_close_cells",
              "in [0, 64]", outline_close_cells);
  nonNegative(outline_min_hole_m2, "outline_min_hole_m2");
}

void PlaneDetectionOptions::validate(const std::string& where) const {
  table().check(*this, where);
  requireThat(threads >= 0, where, "threads (0: every core)", ">= 0", threads);
  tuning.validate(where + ".tuning");
}

OutlineOptions PlaneDetectionOptions::outlineOptions() const {
  OutlineOptions outline;
  outline.cell_m = tuning.outline_cell_fraction * cell_size_m;
  outline.close_cells = tuning.outline_close_cells;
  outline.min_hole_m2 = tuning.outline_min_hole_m2;
  return outline;
}

const params::Table<PlaneDetectionOptions>& PlaneDetectionOptions::table() {
  static const params::Table<PlaneDetectionOptions> t = [] {
    using O = PlaneDetectionOptions;
    params::Table<O> p;
    p.add("distance_threshold_m", &O::distance_threshold_m,
          "RANSAC inlier band around a plane (paper: 20 cm)")
        .unitIs("m")
        .positive()
        .mayBeAuto();
    p.add("max_iterations", &O::max_iterations, "RANSAC iterations per plane (paper: 200)")
        .atLeast(1);
    p.add("min_area_m2", &O::min_area_m2, "planes smaller than this are objects (paper: 2 m²)")
        .unitIs("m²")
        .atLeast(0);
    p.add("plane_cluster_tolerance_m", &O::cluster_tolerance_m,
          "neighbour distance that joins a plane's inliers into one cluster")
        .unitIs("m")
        .positive()
        .mayBeAuto();
    p.add("area_cell_m", &O::cell_size_m,
          "cell of the occupied area and of the outline: area = occupied cells × cell²")
        .unitIs("m")
        .positive()
        .mayBeAuto();
    p.add("min_inliers", &O::min_inliers, "a plane with fewer points is an object")
        .atLeast(3)
        .mayBeAuto();
    p.add("max_planes", &O::max_planes, "stop after this many accepted planes").atLeast(0);
    p.add("max_failures", &O::max_failures, "stop after this many consecutive rejected candidates")
        .atLeast(1);
    p.add("seed", &O::seed, "RANSAC seed (the same inputs give the same planes)").atLeast(0);
    p.add("viewpoint", &O::viewpoint,
          "sensor position [x, y, z] that orients a normal when free space is ambiguous")
        .unitIs("m")
        .mayBeAuto();
    p.add("open_voxel_m", &O::open_voxel_m,
          "voxel of the openness rays (no sensor position): a sparse wall blocks them")
        .unitIs("m")
        .positive()
        .mayBeAuto();
    p.add("boundary", &O::boundary,
          "outline (occupied cells with holes) or convex (the paper's convex hull)")
        .oneOf({"outline", "convex"});
    return p;
  }();
  return t;
}

PlaneDetectionResult detectPlanes(const PointList& cloud, const PlaneDetectionOptions& options) {
  options.validate();
  PlaneDetectionResult result;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!cloud[i].allFinite()) {
      throw InputError("perception: point " + std::to_string(i) + " is not finite");
    }
  }
  if (cloud.size() < 3 || options.max_planes == 0) {
    result.remaining = cloud;
    return result;
  }

  const Aabb box = boundingBox(cloud);
  const Vec3 origin = 0.5 * (box.min + box.max);  // PCL works in float near its origin
  const PclCloud::Ptr pcl_cloud = toPclCloud(cloud, origin);

  std::mt19937 rng(options.seed);
  std::vector<Index> pool(cloud.size());
  std::iota(pool.begin(), pool.end(), Index{0});
  std::vector<char> in_surface(cloud.size(), 0);
  const std::unique_ptr<OccupiedVoxels> occupied = lineOfSightVoxels(cloud, options);
  int failures = 0;
  // Two steps in flight (judgeCandidate): the next one is guessed while a surface is built.
  const bool guess_ahead = (options.threads == 0 ? hardwareThreads() : options.threads) > 1;
  std::optional<CandidateStep> taken;  // the next step, when the guess was right
  const DetectionContext context{pcl_cloud, cloud, origin, occupied.get()};

  while (static_cast<int>(result.surfaces.size()) < options.max_planes &&
         failures < options.max_failures && pool.size() >= 3) {
    CandidateStep step = taken ? std::move(*taken) : nextCandidate(context, pool, options, rng);
    taken.reset();
    if (step.stop) break;
    ++result.stats.candidates;
    const std::vector<Index>& band = step.band;
    const std::vector<Index>& kept = step.kept;

    bool accepted = false;
    if (kept.size() >= static_cast<std::size_t>(std::max(3, options.min_inliers))) {
      const bool guess_next =
          guess_ahead && static_cast<int>(result.surfaces.size()) + 1 < options.max_planes;
      std::optional<Surface> surface =
          judgeCandidate(step, pool, guess_next, context, options, rng, taken);
      accepted = surface.has_value();
      if (accepted) {
        surface->id = static_cast<int>(result.surfaces.size());
        result.surfaces.push_back(std::move(*surface));
        result.stats.trimmed_points += band.size() - kept.size();
        for (const auto i : kept) in_surface[static_cast<std::size_t>(i)] = 1;
      }
    }
    if (accepted) {
      failures = 0;
    } else {
      ++result.stats.rejected_small;
      ++failures;
    }
    // The candidate's points are never proposed again. Accepted: the kept cluster
    // leaves the pool and the trimmed groups stay in it (they may form their own
    // surface). Rejected: every cluster of the band is at most as large as the
    // rejected one, so the whole band leaves the pool (it stays in `remaining`);
    // otherwise a plane made of many small coplanar patches would use up
    // max_failures one patch at a time before larger planes are reached.
    if (accepted) {
      removeFromPool(pool, kept);
    } else {
      removeFromPool(pool, band.size() >= 3 ? band : step.candidate);
    }
  }

  result.remaining.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (in_surface[i] == 0) result.remaining.push_back(cloud[i]);
  }
  return result;
}

}  // namespace uavip::perception
