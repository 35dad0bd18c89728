// The solids of the collision world against independent references: analytic
// distances to a box and to a surface's slab, the hull of a cube's corners against
// the cube, obstacle pieces against the cluster, shell samples against the surface.
#include "uavip/world/solids.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <set>
#include <tuple>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"

namespace uavip::world {
namespace {

constexpr double kTol = 1e-9;

/// The axis-aligned box [lo, hi] as a prism: its top face (z = hi.z) pushed down.
Polyhedron boxSolid(const Vec3& lo, const Vec3& hi) {
  return prism({Vec3(lo.x(), lo.y(), hi.z()), Vec3(hi.x(), lo.y(), hi.z()),
                Vec3(hi.x(), hi.y(), hi.z()), Vec3(lo.x(), hi.y(), hi.z())},
               Vec3(0.0, 0.0, hi.z() - lo.z()));
}

/// Analytic distance from p to the box [lo, hi] (0 inside).
double boxDistance(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return (p - p.cwiseMax(lo).cwiseMin(hi)).norm();
}

/// Distance from p inside or on the box [lo, hi] to its surface.
double boxDepth(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return std::min((p - lo).minCoeff(), (hi - p).minCoeff());
}

/// Minimum of f(t) over t ∈ [0, 1] for a convex f (the distance to a convex set
/// along a segment): golden-section search, then the ends.
template <typename F>
double convexMinimum(const F& f) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double lo = 0.0, hi = 1.0;
  while (hi - lo > 1e-13) {
    const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    if (f(x1) < f(x2)) {
      hi = x2;
    } else {
      lo = x1;
    }
  }
  return std::min({f(0.0), f(1.0), f(0.5 * (lo + hi))});
}

Vec3 randomPoint(std::mt19937& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  return {u(rng), u(rng), u(rng)};
}

TEST(Solids, BoxDistancesMatchTheAnalyticBox) {
  const Vec3 lo(-1.0, 0.5, 2.0), hi(2.0, 1.5, 4.0);
  const Polyhedron box = boxSolid(lo, hi);
  ASSERT_EQ(box.triangles.size(), 12u);
  EXPECT_NEAR((box.bounds().min - lo).norm(), 0.0, kTol);
  EXPECT_NEAR((box.bounds().max - hi).norm(), 0.0, kTol);
  std::mt19937 rng(7);
  for (int i = 0; i < 400; ++i) {
    const Vec3 p = randomPoint(rng, -3.0, 6.0);
    EXPECT_EQ(box.contains(p), boxDistance(p, lo, hi) == 0.0);
    Vec3 q;
    const double d = box.distance(p, p, q);
    EXPECT_NEAR(d, boxDistance(p, lo, hi), kTol);
    EXPECT_NEAR(boxDistance(q, lo, hi), 0.0, kTol);  // the nearest point is the box's
    EXPECT_NEAR((q - p).norm(), d, kTol);
  }
  for (int i = 0; i < 400; ++i) {
    const Vec3 a = randomPoint(rng, -3.0, 6.0), b = randomPoint(rng, -3.0, 6.0);
    const double ref =
        convexMinimum([&](double t) { return boxDistance(a + t * (b - a), lo, hi); });
    Vec3 q;
    const double d = box.distance(a, b, q);
    EXPECT_NEAR(d, ref, 1e-7) << "segment " << a.transpose() << " -> " << b.transpose();
    EXPECT_NEAR(boxDistance(q, lo, hi), 0.0, kTol);
    EXPECT_NEAR(pointSegmentDistance(q, a, b), d, 1e-7);
  }
}

TEST(Solids, SegmentThroughTheBoxIsAtDistanceZero) {
  const Polyhedron box = boxSolid(Vec3::Zero(), Vec3::Ones());
  Vec3 q;
  EXPECT_EQ(box.distance(Vec3(-1.0, 0.5, 0.5), Vec3(2.0, 0.5, 0.5), q), 0.0);
  EXPECT_EQ(box.distance(Vec3(0.5, 0.5, -3.0), Vec3(0.5, 0.5, 3.0), q), 0.0);
  EXPECT_NEAR(box.distance(Vec3(-1.0, 2.0, 0.5), Vec3(2.0, 2.0, 0.5), q), 1.0, kTol);
}

/// A rectangle [0, w] × [0, h] in the frame (origin; u, v = n × u) with normal n,
/// its boundary given with extra points on its edges and inside (the hull drops them).
Surface rectangle(const Vec3& origin, const Vec3& n, const Vec3& u, double w, double h) {
  Surface s;
  s.id = 3;
  s.plane.normal = n;
  s.plane.offset = -n.dot(origin);
  s.axis_u = u;
  s.axis_v = n.cross(u);
  const Vec3 v = s.axis_v;
  s.boundary = {origin,
                origin + 0.5 * w * u,
                origin + w * u,
                origin + w * u + h * v,
                origin + 0.3 * w * u + 0.4 * h * v,
                origin + h * v};
  s.centroid = origin + 0.5 * w * u + 0.5 * h * v;
  return s;
}

TEST(Solids, SurfaceSlabIsTheRectangleExtrudedBehindThePlane) {
  const Vec3 n = Vec3(1.0, -2.0, 0.5).normalized();
  const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
  const Vec3 origin(10.0, -4.0, 3.0);
  const double w = 4.0, h = 2.5, t = 0.05;
  const Polyhedron slab = surfaceSlab(rectangle(origin, n, u, w, h), t);
  ASSERT_FALSE(slab.triangles.empty());
  // In the rectangle's frame the slab is the box [0, w] × [0, h] × [−t, 0].
  const Vec3 lo(0.0, 0.0, -t), hi(w, h, 0.0);
  const auto local = [&](const Vec3& p) {
    return Vec3((p - origin).dot(u), (p - origin).dot(v), (p - origin).dot(n));
  };
  std::mt19937 rng(11);
  for (int i = 0; i < 400; ++i) {
    const Vec3 p = origin + randomPoint(rng, -3.0, 6.0);
    Vec3 q;
    EXPECT_NEAR(slab.distance(p, p, q), boxDistance(local(p), lo, hi), kTol);
    EXPECT_EQ(slab.contains(p), boxDistance(local(p), lo, hi) <= 1e-12)
        << "point " << local(p).transpose();
  }
  // The face the UAV sees is the plane: a point 1 m in front of the middle is 1 m away.
  Vec3 q;
  EXPECT_NEAR(slab.distance(origin + 2.0 * u + 1.0 * v + n, origin + 2.0 * u + 1.0 * v + n, q), 1.0,
              kTol);
}

TEST(Solids, DegenerateSurfaceHasNoSlab) {
  Surface s = rectangle(Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitX(), 2.0, 1.0);
  s.boundary = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};  // collinear
  EXPECT_TRUE(surfaceSlab(s, 0.05).triangles.empty());
  s.boundary.clear();
  EXPECT_TRUE(surfaceSlab(s, 0.05).triangles.empty());
}

/// The 8 corners of the cube [lo, lo + edge]³, then `inside` random points within it.
PointList cubePoints(const Vec3& lo, double edge, int inside, std::mt19937& rng) {
  PointList pts;
  for (int i = 0; i < 8; ++i) pts.push_back(lo + edge * Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  for (int i = 0; i < inside; ++i) pts.push_back(lo + randomPoint(rng, 0.0, edge));
  return pts;
}

TEST(Solids, HullOfACubesCornersIsTheCube) {
  std::mt19937 rng(3);
  const Vec3 lo(100.0, -50.0, 7.0);
  const double edge = 2.0;
  const Vec3 hi = lo + Vec3::Constant(edge);
  for (const int inside : {0, 50}) {
    const PointList pts = cubePoints(lo, edge, inside, rng);
    const Polyhedron hull = hullSolid(pts, lo + Vec3::Constant(0.5 * edge));
    ASSERT_FALSE(hull.triangles.empty());
    EXPECT_EQ(hull.vertices.size(), 8u);  // interior points are no vertex
    EXPECT_NEAR((hull.bounds().min - lo).norm(), 0.0, 1e-9);
    EXPECT_NEAR((hull.bounds().max - hi).norm(), 0.0, 1e-9);
    for (const auto& p : pts) EXPECT_TRUE(hull.contains(p));
    for (int i = 0; i < 300; ++i) {
      const Vec3 p = lo + randomPoint(rng, -2.0, 4.0);
      Vec3 q;
      EXPECT_NEAR(hull.distance(p, p, q), boxDistance(p, lo, hi), 1e-9);
    }
    // An obstacle of the same points is that hull (it spans a volume).
    Obstacle o;
    o.points = pts;
    const Polyhedron solid = obstacleSolid(o, 0.02);
    EXPECT_EQ(solid.vertices.size(), 8u);
    EXPECT_NEAR((solid.bounds().max - hi).norm(), 0.0, 1e-9);
  }
}

/// Euclidean projection of p onto the octahedron |x| + |y| + |z| ≤ 1 (the l1 ball):
/// |p| projected onto the simplex (sort, threshold), the signs put back.
Vec3 projectOntoOctahedron(const Vec3& p) {
  const Vec3 a = p.cwiseAbs();
  if (a.sum() <= 1.0) return p;
  std::array<double, 3> u{a.x(), a.y(), a.z()};
  std::sort(u.begin(), u.end(), std::greater<>());
  double sum = 0.0, theta = 0.0;
  for (int j = 0; j < 3; ++j) {
    sum += u[static_cast<std::size_t>(j)];
    const double t = (sum - 1.0) / (j + 1);
    if (u[static_cast<std::size_t>(j)] - t > 0.0) theta = t;
  }
  const Vec3 w = (a.array() - theta).max(0.0).matrix();
  return w.cwiseProduct(
      Vec3(p.x() < 0 ? -1.0 : 1.0, p.y() < 0 ? -1.0 : 1.0, p.z() < 0 ? -1.0 : 1.0));
}

TEST(Solids, HullOfAnOctahedronIsTheL1Ball) {
  const PointList pts = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0),      Vec3(0, -1, 0),
                         Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(0.1, 0.2, 0.3)};
  const Polyhedron hull = hullSolid(pts, Vec3::Zero());
  ASSERT_EQ(hull.triangles.size(), 8u);
  std::mt19937 rng(5);
  for (int i = 0; i < 500; ++i) {
    const Vec3 p = randomPoint(rng, -1.2, 1.2);
    const double l1 = p.cwiseAbs().sum();
    if (std::abs(l1 - 1.0) < 1e-6) continue;  // too close to a face to call
    EXPECT_EQ(hull.contains(p), l1 < 1.0) << p.transpose();
    Vec3 q;
    EXPECT_NEAR(hull.distance(p, p, q), (p - projectOntoOctahedron(p)).norm(), 1e-9);
    EXPECT_NEAR((q - projectOntoOctahedron(p)).norm(), 0.0, 1e-9);
  }
}

TEST(Solids, FlatHullFailsAndFlatObstacleIsAThinBox) {
  PointList flat;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 4; ++j) flat.emplace_back(0.5 * i, 0.3 * j, 1.0);
  }
  EXPECT_TRUE(hullSolid(flat, Vec3(1.0, 0.45, 1.0)).triangles.empty());
  Obstacle o;
  o.points = flat;
  const Polyhedron box = obstacleSolid(o, 0.1);
  ASSERT_EQ(box.vertices.size(), 8u);
  for (const auto& p : flat) EXPECT_TRUE(box.contains(p));
  const Aabb b = box.bounds();  // PCA axes are the world axes here
  EXPECT_NEAR(b.max.z() - b.min.z(), 0.1, 1e-9);
  EXPECT_NEAR(b.max.x() - b.min.x(), 2.0, 1e-9);
  EXPECT_NEAR(b.max.y() - b.min.y(), 0.9, 1e-9);
  EXPECT_TRUE(obstacleSolid(Obstacle{}, 0.1).triangles.empty());
  o.points = {Vec3(1.0, 2.0, 3.0)};  // one point: a cube of the minimum edge about it
  const Aabb one = obstacleSolid(o, 0.1).bounds();
  EXPECT_NEAR((one.max - one.min - Vec3::Constant(0.1)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((0.5 * (one.max + one.min) - o.points[0]).norm(), 0.0, 1e-9);
}

TEST(Solids, PiecesPartitionAWideCluster) {
  std::mt19937 rng(9);
  Obstacle o;
  o.id = 42;
  for (int i = 0; i < 2000; ++i) {  // seven unit cubes of points along x ∈ [0, 10]
    o.points.push_back(randomPoint(rng, 0.0, 1.0) + Vec3(1.5 * (i % 7), 0.0, 0.0));
  }
  const Aabb box = boundingBox(o.points);
  o.aabb_min = box.min;
  o.aabb_max = box.max;
  const double edge = 4.0;
  const std::vector<Obstacle> pieces = obstaclePieces(o, edge);
  ASSERT_GE(pieces.size(), 3u);  // 10 m wide: at least ⌈10 / 4⌉ cells
  std::multiset<std::tuple<double, double, double>> all, joined;
  for (const auto& p : o.points) all.insert({p.x(), p.y(), p.z()});
  for (const auto& piece : pieces) {
    EXPECT_EQ(piece.id, 42);
    const Aabb b = boundingBox(piece.points);
    EXPECT_TRUE(((b.max - b.min).array() <= edge).all());
    EXPECT_EQ((piece.aabb_min - b.min).norm() + (piece.aabb_max - b.max).norm(), 0.0);
    for (const auto& p : piece.points) joined.insert({p.x(), p.y(), p.z()});
  }
  EXPECT_EQ(joined, all);
  EXPECT_EQ(obstaclePieces(o, 20.0).size(), 1u);  // narrower than the edge: whole
}

TEST(Solids, ShellSamplesLieOnTheSurfaceAndCoverIt) {
  // A cube: its faces are cut into right isosceles triangles, sampled in rows
  // parallel to the hypotenuse at most `spacing` apart, each row's samples at most
  // `spacing` apart, so every point of a face is within spacing/√2 of a sample point
  // (its nearer row is ≤ spacing/2 away, the 45° legs add at most as much along it).
  const Vec3 lo(1.0, 2.0, 0.0), hi(3.0, 4.0, 2.0);
  const double spacing = 0.1;
  const std::vector<Polyhedron> solids = {boxSolid(lo, hi), Polyhedron{}};
  const PointList samples = shellSamples(solids, spacing);
  ASSERT_FALSE(samples.empty());
  // A sample is the centre of a voxel holding a point of the surface.
  const double half_diagonal = 0.5 * std::sqrt(3.0) * spacing + 1e-9;
  for (const auto& s : samples) {
    const double off = boxDistance(s, lo, hi) > 0.0 ? boxDistance(s, lo, hi) : boxDepth(s, lo, hi);
    EXPECT_LE(off, half_diagonal) << s.transpose();
  }
  std::set<std::tuple<double, double, double>> unique;
  for (const auto& s : samples) unique.insert({s.x(), s.y(), s.z()});
  EXPECT_EQ(unique.size(), samples.size());
  // Every point of the surface has a sample near: rows ≤ spacing apart, then the voxel.
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> t(0.0, 1.0);
  for (int i = 0; i < 300; ++i) {
    Vec3 p = lo + (hi - lo).cwiseProduct(Vec3(t(rng), t(rng), t(rng)));
    const int axis = i % 3;
    p[axis] = (i / 3) % 2 ? hi[axis] : lo[axis];  // onto a face
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& s : samples) nearest = std::min(nearest, (s - p).norm());
    EXPECT_LE(nearest, spacing * (1.0 / std::sqrt(2.0) + 0.5 * std::sqrt(3.0)) + 1e-9);
  }
  EXPECT_THROW(shellSamples(solids, 0.0), InputError);
  EXPECT_TRUE(shellSamples({Polyhedron{}}, spacing).empty());
}

/// Depth of p inside a convex solid: its distance to the nearest face plane, negative
/// outside some face [m].
double depth(const Polyhedron& solid, const Vec3& p) {
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < solid.normals.size(); ++f)
    d = std::min(d, -(solid.normals[f].dot(p) + solid.offsets[f]));
  return d;
}

/// The samples marked in a grid of edge `edge` (the planning grid's lattice), then a
/// flood over its free voxels from a corner outside, stepping to the 6 face
/// neighbours: the centres of the voxels it reaches.
PointList floodFromOutside(const PointList& samples, double edge) {
  const Vec3 origin = boundingBox(samples).min - Vec3::Constant(1.5 * edge);
  const auto key = [&](const Vec3& p) {
    const Eigen::Vector3i k = ((p - origin) / edge).array().floor().cast<int>();
    return std::tuple<int, int, int>{k.x(), k.y(), k.z()};
  };
  const auto [nx, ny, nz] = key(boundingBox(samples).max + Vec3::Constant(1.5 * edge));
  std::set<std::tuple<int, int, int>> occupied;
  for (const auto& s : samples) occupied.insert(key(s));
  std::set<std::tuple<int, int, int>> seen = {{0, 0, 0}};
  std::vector<std::tuple<int, int, int>> todo = {{0, 0, 0}};
  PointList reached;
  while (!todo.empty()) {
    const auto [x, y, z] = todo.back();
    todo.pop_back();
    reached.push_back(origin + edge * (Vec3(x, y, z) + Vec3::Constant(0.5)));
    for (int n = 0; n < 6; ++n) {
      const int step = n % 2 ? 1 : -1;
      const std::tuple<int, int, int> m{x + (n / 2 == 0 ? step : 0), y + (n / 2 == 1 ? step : 0),
                                        z + (n / 2 == 2 ? step : 0)};
      const auto [mx, my, mz] = m;
      if (std::min({mx, my, mz}) < 0 || mx > nx || my > ny || mz > nz || occupied.count(m) ||
          !seen.insert(m).second)
        continue;
      todo.push_back(m);
    }
  }
  return reached;
}

TEST(Solids, ShellSamplesSealTheSolidInAGridOfTwiceTheirSpacing) {
  // The planning grid marks the samples taken at half its resolution
  // (app::planningGrid): then no free voxel wholly inside a solid can be reached from
  // outside through free faces. (Diagonal steps can slip between the marked voxels of
  // a hull: the grid's inflation by √3 · resolution closes those gaps.)
  std::mt19937 rng(4);
  Obstacle o;
  for (int i = 0; i < 40; ++i) o.points.push_back(Vec3(5.0, 1.0, 2.0) + randomPoint(rng, 0.0, 3.0));
  const std::vector<Polyhedron> solids = {boxSolid(Vec3::Zero(), Vec3(3.0, 1.0, 2.0)),
                                          obstacleSolid(o, 0.02)};
  ASSERT_GT(solids[1].triangles.size(), 12u);  // a hull, not a box
  for (const double edge : {0.2, 0.37}) {
    const PointList reached = floodFromOutside(shellSamples(solids, 0.5 * edge), edge);
    ASSERT_GT(reached.size(), 100u);
    const double half_diagonal = 0.5 * std::sqrt(3.0) * edge;
    for (const auto& c : reached) {
      for (const auto& solid : solids) EXPECT_LE(depth(solid, c), half_diagonal) << c.transpose();
    }
  }
}

TEST(Solids, ShellSamplesSkipOccupiedVoxelsAndStayInTheRegion) {
  const Vec3 lo(0.0, 0.0, 0.0), hi(2.0, 2.0, 2.0);
  const double spacing = 0.25;
  const std::vector<Polyhedron> solids = {boxSolid(lo, hi)};
  const PointList all = shellSamples(solids, spacing);
  // A measured point at a sample's voxel centre removes exactly that sample.
  const PointList occupied = {all[0], all[all.size() / 2]};
  const PointList rest = shellSamples(solids, spacing, {&occupied});
  EXPECT_EQ(rest.size(), all.size() - 2);
  for (const auto& s : rest) {
    for (const auto& o : occupied) EXPECT_GT((s - o).norm(), 1e-9);
  }
  const Aabb region{Vec3(-1.0, -1.0, -1.0), Vec3(1.0, 3.0, 0.5)};
  const PointList part = shellSamples(solids, spacing, {}, &region);
  ASSERT_FALSE(part.empty());
  EXPECT_LT(part.size(), all.size());
  const Vec3 slack = Vec3::Constant(0.5 * spacing + 1e-9);  // a sample's voxel centre
  for (const auto& s : part) {
    EXPECT_TRUE(((s.array() >= (region.min - slack).array()).all()) &&
                ((s.array() <= (region.max + slack).array()).all()))
        << s.transpose();
  }
  const Aabb away{Vec3(10.0, 10.0, 10.0), Vec3(11.0, 11.0, 11.0)};
  EXPECT_TRUE(shellSamples(solids, spacing, {}, &away).empty());
}

}  // namespace
}  // namespace uavip::world
