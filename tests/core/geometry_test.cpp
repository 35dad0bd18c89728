// Tests of core/geometry.h against brute force and known shapes.
#include "uavip/core/geometry.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "uavip/core/text.h"

namespace uavip {
namespace {

/// Brute force: minimum distance to n+1 evenly spaced points of [a, b].
double bruteSegmentDistance(const Vec3& p, const Vec3& a, const Vec3& b, int n) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i) best = std::min(best, (p - (a + (double(i) / n) * (b - a))).norm());
  return best;
}

TEST(Geometry, PointSegmentDistanceMatchesBruteForce) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  const int n = 20000;
  for (int k = 0; k < 200; ++k) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), p(u(rng), u(rng), u(rng));
    const double exact = pointSegmentDistance(p, a, b);
    const double brute = bruteSegmentDistance(p, a, b, n);
    // Sampling overestimates by at most half a sample step.
    EXPECT_LE(exact, brute + 1e-12);
    EXPECT_GE(exact, brute - 0.5 * (b - a).norm() / n - 1e-12);
  }
}

TEST(Geometry, SegmentSegmentDistanceMatchesDenseSampling) {
  // Random segments, some of them points, parallel or collinear, against the least
  // distance over a 401 × 401 grid of pairs of points along them.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> d(-5.0, 5.0);
  const auto point = [&] {
    const double x = d(rng);
    const double y = d(rng);
    const double z = d(rng);
    return Vec3(x, y, z);
  };
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 a0 = point();
    Vec3 a1 = point();
    const Vec3 b0 = point();
    Vec3 b1 = point();
    if (trial % 7 == 0) b1 = b0;                                                       // a point
    if (trial % 13 == 0) a1 = a0;                                                      // a point
    if (trial % 11 == 0) a1 = a0 + 0.5 * (b1 - b0);                                    // parallel
    if (trial % 17 == 0) a1 = b0 + 0.3 * (b1 - b0);                                    // touching
    if (trial % 19 == 0) a1 = a0 + 1e-7 * (b1 - b0).cross(Vec3(1, 2, 3)) + (b1 - b0);  // ~parallel
    double best = std::numeric_limits<double>::infinity();
    const int n = 400;
    for (int i = 0; i <= n; ++i)
      for (int k = 0; k <= n; ++k) {
        const Vec3 a = a0 + (a1 - a0) * (static_cast<double>(i) / n);
        const Vec3 b = b0 + (b1 - b0) * (static_cast<double>(k) / n);
        best = std::min(best, (a - b).norm());
      }
    Vec3 on_a;
    Vec3 on_b;
    const double exact = segmentSegmentDistance(a0, a1, b0, b1, &on_a, &on_b);
    EXPECT_LE(exact, best + 1e-9) << trial;
    EXPECT_NEAR(exact, best, 0.05) << trial;  // grid step ≤ 17.4 m / 400
    EXPECT_NEAR((on_a - on_b).norm(), exact, 1e-12);
    // The closest points lie on their segments.
    EXPECT_NEAR(pointSegmentDistance(on_a, a0, a1), 0.0, 1e-9);
    EXPECT_NEAR(pointSegmentDistance(on_b, b0, b1), 0.0, 1e-9);
    EXPECT_NEAR(segmentSegmentDistance(b0, b1, a0, a1), exact, 1e-9);  // symmetric
    // The boxes' distance never exceeds the brute-force least distance.
    EXPECT_LE(segmentBoxesDistance(a0, a1, b0, b1), best + 1e-9) << trial;
  }
}

TEST(Geometry, SegmentBoxesDistanceKnownCases) {
  // Parallel to one axis: the boxes' gap is the segments' distance.
  EXPECT_NEAR(segmentBoxesDistance({0, 0, 0}, {1, 0, 0}, {3, 0, 0}, {5, 0, 0}), 2.0, 1e-12);
  EXPECT_NEAR(segmentBoxesDistance({0, 0, 0}, {0, 0, 4}, {3, 4, 1}, {3, 4, 2}), 5.0, 1e-12);
  // Diagonals of the unit square cross: boxes meet.
  EXPECT_EQ(segmentBoxesDistance({0, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 0, 0}), 0.0);
  // Skew segments in the planes x = 0 and x = 1 whose projections on x = 0 cross: the
  // boxes are 1 m apart in x, and so are the segments.
  EXPECT_NEAR(segmentBoxesDistance({0, 0, 0}, {0, 2, 2}, {1, 0, 2}, {1, 2, 0}), 1.0, 1e-12);
  EXPECT_NEAR(segmentSegmentDistance({0, 0, 0}, {0, 2, 2}, {1, 0, 2}, {1, 2, 0}), 1.0, 1e-12);
  // Segments whose boxes are far below their distance: a bound, not the distance.
  EXPECT_EQ(segmentBoxesDistance({0, 0, 0}, {4, 4, 0}, {0, 3, 0}, {1, 4, 0}), 0.0);
  EXPECT_GT(segmentSegmentDistance({0, 0, 0}, {4, 4, 0}, {0, 3, 0}, {1, 4, 0}), 2.0);
}

TEST(Geometry, SegmentSegmentDistanceKnownCases) {
  // Crossing at right angles 2 m apart, parallel 3 m apart, collinear 1 m apart.
  EXPECT_NEAR(segmentSegmentDistance({-1, 0, 0}, {1, 0, 0}, {0, -1, 2}, {0, 1, 2}), 2.0, 1e-12);
  EXPECT_NEAR(segmentSegmentDistance({0, 0, 0}, {4, 0, 0}, {1, 3, 0}, {2, 3, 0}), 3.0, 1e-12);
  EXPECT_NEAR(segmentSegmentDistance({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 0, 0}), 1.0, 1e-12);
  EXPECT_NEAR(segmentSegmentDistance({0, 0, 0}, {0, 0, 0}, {3, 4, 0}, {3, 4, 0}), 5.0, 1e-12);
}

TEST(Geometry, PointSegmentDistanceKnownCases) {
  const Vec3 a(0, 0, 0), b(2, 0, 0);
  EXPECT_NEAR(pointSegmentDistance(Vec3(1, 3, 4), a, b), 5.0, 1e-12);   // interior
  EXPECT_NEAR(pointSegmentDistance(Vec3(-3, 4, 0), a, b), 5.0, 1e-12);  // before a
  EXPECT_NEAR(pointSegmentDistance(Vec3(5, 0, 4), a, b), 5.0, 1e-12);   // past b
  EXPECT_NEAR(pointSegmentDistance(Vec3(1, 0, 0), a, b), 0.0, 1e-12);   // on it
  // Degenerate segment: distance to the point.
  EXPECT_NEAR(pointSegmentDistance(Vec3(1, 2, 2), a, a), 3.0, 1e-12);
}

/// Rotation taking the xy plane to a tilted plane, plus a translation.
PointList placeTilted(const std::vector<Eigen::Vector2d>& poly2d) {
  const Eigen::Matrix3d r =
      (Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()) * Eigen::AngleAxisd(-0.4, Vec3::UnitX()))
          .toRotationMatrix();
  const Vec3 t(10.0, -4.0, 2.5);
  PointList out;
  for (const auto& q : poly2d) out.push_back(r * Vec3(q.x(), q.y(), 0.0) + t);
  return out;
}

TEST(Geometry, PolygonAreaOfKnownPolygonsInTiltedPlanes) {
  // Rectangle 3 × 2.
  EXPECT_NEAR(polygonArea(placeTilted({{0, 0}, {3, 0}, {3, 2}, {0, 2}})), 6.0, 1e-9);
  // Right triangle with legs 4, 5 → 10.
  EXPECT_NEAR(polygonArea(placeTilted({{0, 0}, {4, 0}, {0, 5}})), 10.0, 1e-9);
  // Clockwise order gives the same (unsigned) area.
  EXPECT_NEAR(polygonArea(placeTilted({{0, 2}, {3, 2}, {3, 0}, {0, 0}})), 6.0, 1e-9);
  // Regular hexagon of circumradius 1: 3√3/2.
  std::vector<Eigen::Vector2d> hex;
  hex.reserve(6);
  for (int i = 0; i < 6; ++i) hex.emplace_back(std::cos(i * M_PI / 3), std::sin(i * M_PI / 3));
  EXPECT_NEAR(polygonArea(placeTilted(hex)), 1.5 * std::sqrt(3.0), 1e-9);
  // Non-convex L shape: 2×2 square minus a 1×1 corner = 3.
  EXPECT_NEAR(polygonArea(placeTilted({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}})), 3.0,
              1e-9);
  // A vertical wall 8 × 4 (as in the coverage tests).
  EXPECT_NEAR(polygonArea({Vec3(2, 0, 0), Vec3(2, 8, 0), Vec3(2, 8, 4), Vec3(2, 0, 4)}), 32.0,
              1e-12);
  // Fewer than 3 vertices.
  EXPECT_EQ(polygonArea({}), 0.0);
  EXPECT_EQ(polygonArea({Vec3(0, 0, 0), Vec3(1, 1, 1)}), 0.0);
}

TEST(Geometry, BoundingBox) {
  const Aabb empty = boundingBox({});
  EXPECT_TRUE(empty.empty());
  const Aabb box = boundingBox({Vec3(1, -2, 3), Vec3(-1, 5, 0), Vec3(0, 0, 7)});
  EXPECT_FALSE(box.empty());
  EXPECT_EQ(box.min, Vec3(-1, -2, 0));
  EXPECT_EQ(box.max, Vec3(1, 5, 7));
  const Aabb single = boundingBox({Vec3(4, 4, 4)});
  EXPECT_FALSE(single.empty());
  EXPECT_EQ(single.min, single.max);
}

TEST(Geometry, PolylineLength) {
  EXPECT_EQ(polylineLength({}), 0.0);
  EXPECT_EQ(polylineLength({Vec3(1, 2, 3)}), 0.0);
  EXPECT_NEAR(polylineLength({Vec3(0, 0, 0), Vec3(3, 4, 0), Vec3(3, 4, 12)}), 5.0 + 12.0, 1e-12);
}

TEST(Geometry, AllFinite) {
  EXPECT_TRUE(allFinite({}));
  EXPECT_TRUE(allFinite({Vec3(1, 2, 3), Vec3(-1e300, 0, 0)}));
  EXPECT_FALSE(allFinite({Vec3(1, 2, 3), Vec3(0, std::numeric_limits<double>::quiet_NaN(), 0)}));
  EXPECT_FALSE(allFinite({Vec3(0, 0, std::numeric_limits<double>::infinity())}));
}

using Vec2 = Eigen::Vector2d;

/// z of (a − o) × (b − o), written out independently of the code under test.
double turnOf(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

/// Brute force: the extreme points are the tails of the ordered pairs (a, b) with
/// every point strictly left of a → b or on the segment [a, b] (O(n³)).
std::vector<Vec2> bruteExtremePoints(const std::vector<Vec2>& pts) {
  std::vector<Vec2> out;
  for (const auto& a : pts) {
    bool extreme = false;
    for (const auto& b : pts) {
      if (a == b) continue;
      bool edge = true;
      for (const auto& q : pts) {
        const double t = turnOf(a, b, q);
        const bool on_segment = t == 0.0 && (q - a).dot(b - a) >= 0.0 && (q - b).dot(a - b) >= 0.0;
        if (!(t > 0.0 || on_segment)) {
          edge = false;
          break;
        }
      }
      if (edge) extreme = true;
    }
    const auto same = [&](const Vec2& v) { return v == a; };
    if (extreme && std::none_of(out.begin(), out.end(), same)) out.push_back(a);
  }
  return out;
}

TEST(Geometry, ConvexHull2dMatchesBruteForce) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  for (int trial = 0; trial < 30; ++trial) {
    std::vector<Vec2> pts;
    pts.reserve(40 + static_cast<std::size_t>(trial));
    for (int i = 0; i < 40 + trial; ++i) pts.emplace_back(u(rng), u(rng));
    // Collinear points on a square's edges and duplicates: not hull vertices.
    const double h = 12.0;
    for (double t : {-h, -0.5 * h, 0.0, 0.5 * h, h}) {
      pts.emplace_back(t, -h);
      pts.emplace_back(h, t);
    }
    pts.push_back(pts.front());
    const auto hull = convexHull2d(pts);
    ASSERT_GE(hull.size(), 3u);
    // Every point inside or on; the hull strictly convex and counter-clockwise.
    for (std::size_t i = 0; i < hull.size(); ++i) {
      const Vec2& a = hull[i];
      const Vec2& b = hull[(i + 1) % hull.size()];
      EXPECT_GT(turnOf(hull[(i + hull.size() - 1) % hull.size()], a, b), 0.0);
      for (const auto& q : pts) EXPECT_GE(turnOf(a, b, q), 0.0);
    }
    // Its vertices are exactly the extreme points.
    auto brute = bruteExtremePoints(pts);
    auto less = [](const Vec2& l, const Vec2& r) {
      return l.x() < r.x() || (l.x() == r.x() && l.y() < r.y());
    };
    auto sorted_hull = hull;
    std::sort(sorted_hull.begin(), sorted_hull.end(), less);
    std::sort(brute.begin(), brute.end(), less);
    EXPECT_EQ(sorted_hull, brute);
    // Starts at the lowest x.
    EXPECT_EQ(hull.front(), sorted_hull.front());
  }
  // Degenerate sets.
  EXPECT_EQ(convexHull2d({Vec2(1, 1), Vec2(0, 0)}), (std::vector<Vec2>{Vec2(0, 0), Vec2(1, 1)}));
  EXPECT_EQ(convexHull2d({Vec2(0, 0), Vec2(2, 2), Vec2(1, 1)}),
            (std::vector<Vec2>{Vec2(0, 0), Vec2(2, 2)}));
}

TEST(Geometry, PolygonArea2dOfKnownPolygons) {
  // An L of 3 × 3 less 2 × 2 = 5 m², counter-clockwise then clockwise.
  std::vector<Vec2> l{Vec2(0, 0), Vec2(3, 0), Vec2(3, 1), Vec2(1, 1), Vec2(1, 3), Vec2(0, 3)};
  EXPECT_DOUBLE_EQ(polygonTwiceSignedArea2d(l), 10.0);
  EXPECT_DOUBLE_EQ(polygonArea2d(l), 5.0);
  std::reverse(l.begin(), l.end());
  EXPECT_DOUBLE_EQ(polygonTwiceSignedArea2d(l), -10.0);
  EXPECT_DOUBLE_EQ(polygonArea2d(l), 5.0);
  // A regular 64-gon of radius 2 off the origin: (n/2)·r²·sin(2π/n).
  std::vector<Vec2> ngon;
  const int n = 64;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    ngon.emplace_back(50.0 + 2.0 * std::cos(a), -30.0 + 2.0 * std::sin(a));
  }
  EXPECT_NEAR(polygonArea2d(ngon), 0.5 * n * 4.0 * std::sin(2.0 * M_PI / n), 1e-9);
  EXPECT_EQ(polygonArea2d({Vec2(0, 0), Vec2(1, 1)}), 0.0);
}

TEST(Text, ControlCharactersAreEscapedOnOneLine) {
  EXPECT_EQ(escapeControl("two\nlines.xyz"), "two\\nlines.xyz");
  std::string raw = "a\tb\rc";
  raw += '\x01';
  raw += 'd';
  raw += '\x7f';
  raw += '\0';
  raw += 'e';
  EXPECT_EQ(escapeControl(raw), "a\\tb\\rc\\x01d\\x7f\\x00e");
  EXPECT_EQ(escapeControl("gr\xc3\xbcn \xe2\x88\x9e.pcd"),
            "gr\xc3\xbcn \xe2\x88\x9e.pcd");  // UTF-8 is kept
}

}  // namespace
}  // namespace uavip
