// The outline that follows a surface's points (perception/surface_outline.h) against
// brute force: the cells the points occupy, counted directly, and point-in-polygon
// tests of every point against the traced outline and holes.

#include "uavip/perception/surface_outline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <utility>

#include "uavip/core/geometry.h"

namespace uavip::perception {
namespace {

using Vec2 = Eigen::Vector2d;

/// A jittered 5 cm lattice over [0, w] × [0, h] without the points `skip` rejects.
template <typename Skip>
std::vector<Vec2> lattice(double w, double h, Skip skip, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.004, 0.004);
  std::vector<Vec2> out;
  for (double x = 0.0; x <= w + 1e-9; x += 0.05)
    for (double y = 0.0; y <= h + 1e-9; y += 0.05)
      if (!skip(x, y)) out.emplace_back(x + jitter(rng), y + jitter(rng));
  return out;
}

bool onOutline(const Outline2d& o, const Vec2& p) {
  if (!pointInPolygon2d(p, o.outer)) return false;
  for (const auto& h : o.holes)
    if (pointInPolygon2d(p, h)) return false;
  return true;
}

TEST(SurfaceOutline, LShapeFollowsThePointsAndItsAreaIsTheOccupiedCells) {
  // 6 × 2 foot and 2 × 3 arm: the notch [2, 6] × (2, 5] is empty.
  const auto pts = lattice(
      6.0, 5.0, [](double x, double y) { return x > 2.0 + 1e-9 && y > 2.0 + 1e-9; }, 1);
  OutlineOptions o;
  o.cell_m = 0.1;
  const Outline2d out = occupiedOutline2d(pts, o);
  ASSERT_GE(out.outer.size(), 6u);
  EXPECT_TRUE(out.holes.empty());
  EXPECT_GT(polygonTwiceSignedArea2d(out.outer), 0.0);
  EXPECT_EQ(polygonSelfIntersection2d(out.outer).first, -1);
  EXPECT_NEAR(polygonArea2d(out.outer), out.area_m2, 1e-9);
  for (const auto& p : pts) EXPECT_TRUE(onOutline(out, p)) << p.transpose();
  // The notch is air: its middle is outside.
  EXPECT_FALSE(onOutline(out, Vec2(4.0, 3.5)));
  // Brute force: the area is the number of occupied cells of the grid the outline uses
  // (aligned with x here: the smallest rectangle is axis-aligned), within the cells
  // the closing may add along the inner corner.
  std::set<std::pair<long, long>> cells;
  double lox = 1e9, loy = 1e9;
  for (const auto& p : pts) {
    lox = std::min(lox, p.x());
    loy = std::min(loy, p.y());
  }
  for (const auto& p : pts)
    cells.insert({std::lround(std::floor((p.x() - lox) / 0.1)),
                  std::lround(std::floor((p.y() - loy) / 0.1))});
  EXPECT_NEAR(out.area_m2, 0.01 * static_cast<double>(cells.size()), 0.01 * 0.04 * cells.size());
  // Against the L itself: the outline reaches at most half a cell past the points
  // (perimeter 22 m), corners included.
  EXPECT_GE(out.area_m2, 18.0);
  EXPECT_LE(out.area_m2, 18.0 + 22.0 * 0.05 + 6 * 0.01);
}

TEST(SurfaceOutline, WindowIsAHoleAndSmallGapsAreNot) {
  // 8 × 4 with a 2 × 1.5 window and a 0.15 m gap of missing points (filled).
  const auto pts = lattice(
      8.0, 4.0,
      [](double x, double y) {
        const bool window = x > 3.0 && x < 5.0 && y > 1.0 && y < 2.5;
        const bool gap = x > 6.5 && x < 6.65 && y > 3.0 && y < 3.15;
        return window || gap;
      },
      2);
  OutlineOptions o;
  o.cell_m = 0.1;
  const Outline2d out = occupiedOutline2d(pts, o);
  ASSERT_EQ(out.holes.size(), 1u);
  EXPECT_LT(polygonTwiceSignedArea2d(out.holes[0]), 0.0);  // clockwise
  EXPECT_NEAR(polygonArea2d(out.holes[0]), 2.0 * 1.5, 0.1 * 7.0);
  EXPECT_NEAR(polygonArea2d(out.outer) - polygonArea2d(out.holes[0]), out.area_m2, 1e-9);
  EXPECT_FALSE(onOutline(out, Vec2(4.0, 1.75)));
  EXPECT_TRUE(onOutline(out, Vec2(6.57, 3.07)));
  for (const auto& p : pts) EXPECT_TRUE(onOutline(out, p)) << p.transpose();
}

TEST(SurfaceOutline, TurnedPointsGiveTheSameAreaAndOrderDoesNotMatter) {
  auto pts = lattice(
      4.0, 2.0, [](double, double) { return false; }, 3);
  OutlineOptions o;
  o.cell_m = 0.1;
  const Outline2d straight = occupiedOutline2d(pts, o);
  const double a = 0.6;  // turned by 34°: the grid follows the rectangle
  std::vector<Vec2> turned;
  turned.reserve(pts.size());
  for (const auto& p : pts)
    turned.emplace_back(std::cos(a) * p.x() - std::sin(a) * p.y(),
                        std::sin(a) * p.x() + std::cos(a) * p.y());
  const Outline2d t = occupiedOutline2d(turned, o);
  EXPECT_EQ(t.outer.size(), 4u);
  EXPECT_NEAR(t.area_m2, straight.area_m2, 0.02 * straight.area_m2);
  std::reverse(turned.begin(), turned.end());
  const Outline2d r = occupiedOutline2d(turned, o);
  EXPECT_EQ(r.outer, t.outer);
}

}  // namespace
}  // namespace uavip::perception
