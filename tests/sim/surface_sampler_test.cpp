// Tests of sim/: ground-truth primitives and surface sampling, against brute force
// and hand-worked counts.
#include "uavip/sim/surface_sampler.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/sim/world_model.h"

namespace uavip::sim {
namespace {

/// Brute-force distance to a rectangle: minimum over a dense grid of its points.
double bruteRectDistance(const Rect& r, const Vec3& p, int n) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const Vec3 q = r.corner + (double(i) / n) * r.edge_u + (double(j) / n) * r.edge_v;
      best = std::min(best, (p - q).norm());
    }
  }
  return best;
}

Rect tiltedRect() {
  // 2 × 1 m rectangle with orthogonal edges in a tilted plane.
  Rect r;
  r.name = "tilted";
  r.corner = Vec3(1.0, -0.5, 0.3);
  const Vec3 u = Vec3(1.0, 1.0, 0.5).normalized();
  const Vec3 v = u.cross(Vec3(0.2, -1.0, 0.7)).normalized();
  r.edge_u = 2.0 * u;
  r.edge_v = 1.0 * v;
  return r;
}

TEST(WorldModel, RectDistanceMatchesBruteForce) {
  WorldModel world;
  const Rect r = tiltedRect();
  world.addPlane(r);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> box(-2.0, 4.0);
  const int n = 200;  // grid step ≤ 1 cm; brute force overestimates by < half a diagonal
  const double tol = 0.5 * (r.edge_u.norm() + r.edge_v.norm()) / n + 1e-12;
  for (int k = 0; k < 60; ++k) {
    const Vec3 p(box(rng), box(rng), box(rng));
    const double exact = world.distanceToTruth(p);
    const double brute = bruteRectDistance(r, p, n);
    EXPECT_LE(exact, brute + 1e-12) << "p=" << p.transpose();
    EXPECT_GE(exact, brute - tol) << "p=" << p.transpose();
  }
  // A point above the middle is at its height; a point on the plane beyond a corner is
  // at the corner distance.
  const Vec3 c = r.center();
  EXPECT_NEAR(world.distanceToTruth(c + 0.7 * r.normal()), 0.7, 1e-12);
  const Vec3 beyond = r.corner - 0.3 * r.edge_u.normalized() - 0.4 * r.edge_v.normalized();
  EXPECT_NEAR(world.distanceToTruth(beyond), 0.5, 1e-12);
}

TEST(WorldModel, DistanceToSegmentsPointsAndEmpty) {
  WorldModel world;
  EXPECT_TRUE(world.empty());
  EXPECT_TRUE(std::isinf(world.distanceToTruth(Vec3::Zero())));
  world.addLine("pole", Vec3(0, 0, 0), Vec3(0, 0, 2));
  world.addPoint("lamp", Vec3(5, 0, 1));
  EXPECT_FALSE(world.empty());
  EXPECT_NEAR(world.distanceToTruth(Vec3(5, 3, 1)), 3.0, 1e-12);  // to the point
  EXPECT_NEAR(world.distanceToTruth(Vec3(1, 0, 1)), 1.0, 1e-12);  // to the pole
  EXPECT_NEAR(world.distanceToTruth(Vec3(0, 0, 5)), 3.0, 1e-12);  // past the pole's end
}

TEST(WorldModel, BoxFacesPointOutward) {
  for (double yaw : {0.0, 30.0, -115.0}) {
    WorldModel world;
    const Vec3 lo(-1.0, 2.0, 0.0), hi(1.0, 5.0, 1.5);
    world.addBox("box", lo, hi, yaw);
    ASSERT_EQ(world.rects().size(), 6u);
    const Vec3 centre = 0.5 * (lo + hi);
    std::set<std::string> names;
    double total_area = 0.0;
    for (const Rect& r : world.rects()) {
      names.insert(r.name);
      // The face's normal points from the box centre toward the face.
      EXPECT_GT(r.normal().dot(r.center() - centre), 0.0) << r.name << " yaw " << yaw;
      // The normal is parallel to the centre→face vector (faces are axis-aligned boxes).
      EXPECT_NEAR(r.normal().cross((r.center() - centre).normalized()).norm(), 0.0, 1e-9);
      EXPECT_NEAR(r.distance(centre), (r.center() - centre).norm(), 1e-9);
      total_area += r.area();
    }
    EXPECT_EQ(names,
              (std::set<std::string>{"box/+x", "box/-x", "box/+y", "box/-y", "box/+z", "box/-z"}));
    EXPECT_NEAR(total_area, 2.0 * (2.0 * 3.0 + 2.0 * 1.5 + 3.0 * 1.5), 1e-9);
    // The centre is inside: its distance is to the nearest face (half the z size).
    EXPECT_NEAR(world.distanceToTruth(centre), 0.75, 1e-9);
  }
  // Unrotated +x face really is at x = hi.x with normal +x.
  WorldModel world;
  world.addBox("b", Vec3(0, 0, 0), Vec3(1, 2, 3));
  for (const Rect& r : world.rects()) {
    if (r.name == "b/+x") {
      EXPECT_NEAR((r.normal() - Vec3::UnitX()).norm(), 0.0, 1e-12);
      EXPECT_NEAR(r.center().x(), 1.0, 1e-12);
    }
    if (r.name == "b/-z") {
      EXPECT_NEAR((r.normal() + Vec3::UnitZ()).norm(), 0.0, 1e-12);
      EXPECT_NEAR(r.center().z(), 0.0, 1e-12);
    }
  }
  // Yaw 90 turns the "+x" face to face +y.
  WorldModel turned;
  turned.addBox("b", Vec3(0, 0, 0), Vec3(1, 2, 3), 90.0);
  EXPECT_NEAR((turned.rects()[0].normal() - Vec3::UnitY()).norm(), 0.0, 1e-12);
}

TEST(WorldModel, CrossedPlanes) {
  WorldModel world;
  const Vec3 c(1.0, 2.0, 3.0);
  world.addCrossedPlanes("x", c, 4.0, 2.0, 30.0);
  ASSERT_EQ(world.rects().size(), 2u);
  EXPECT_EQ(world.rects()[0].name, "x/a");
  EXPECT_EQ(world.rects()[1].name, "x/b");
  for (const Rect& r : world.rects()) {
    EXPECT_NEAR((r.center() - c).norm(), 0.0, 1e-12);
    EXPECT_NEAR(r.normal().z(), 0.0, 1e-12);  // vertical
    EXPECT_NEAR(r.area(), 8.0, 1e-12);
  }
  EXPECT_NEAR(world.rects()[0].normal().dot(world.rects()[1].normal()), 0.0, 1e-12);
  // Rectangle a runs along the yaw direction.
  const Vec3 dir(std::cos(M_PI / 6), std::sin(M_PI / 6), 0.0);
  EXPECT_NEAR(world.rects()[0].edge_u.normalized().cross(dir).norm(), 0.0, 1e-12);
  // Its end at c + 2·dir is on it, c + 2.5·dir is 0.5 m from it.
  EXPECT_NEAR(world.rects()[0].distance(c + 2.5 * dir), 0.5, 1e-12);
  // Top edge at c.z + 1.
  EXPECT_NEAR(world.distanceToTruth(c + Vec3(0, 0, 1.25)), 0.25, 1e-12);
}

TEST(WorldModel, BadPrimitivesThrow) {
  WorldModel world;
  EXPECT_THROW(world.addLine("l", Vec3(1, 1, 1), Vec3(1, 1, 1)), InputError);
  Rect skew;
  skew.edge_u = Vec3(1, 0, 0);
  skew.edge_v = Vec3(1, 1, 0);
  EXPECT_THROW(world.addPlane(skew), InputError);
  Rect zero;
  zero.edge_v = Vec3::Zero();
  EXPECT_THROW(world.addPlane(zero), InputError);
  EXPECT_THROW(world.addBox("b", Vec3(0, 0, 0), Vec3(1, 0, 1)), InputError);
  EXPECT_THROW(world.addBox("b", Vec3(0, 0, 2), Vec3(1, 1, 1)), InputError);
  EXPECT_THROW(world.addCrossedPlanes("c", Vec3::Zero(), 0.0, 1.0), InputError);
  EXPECT_TRUE(world.empty());
}

TEST(SurfaceSampler, GridCountOfRectangle) {
  WorldModel world;
  Rect r;
  r.name = "r";
  r.edge_u = Vec3(2.0, 0.0, 0.0);
  r.edge_v = Vec3(0.0, 1.0, 0.0);
  world.addPlane(r);
  SampleOptions opt;
  opt.spacing_m = 0.1;
  opt.noise_sigma_m = 0.0;
  const PointList pts = sampleSurfaces(world, opt);
  ASSERT_EQ(pts.size(), 21u * 11u);
  // Without noise: every point is on the grid (multiples of 0.1) and both ends are in.
  const Aabb box = boundingBox(pts);
  EXPECT_NEAR((box.min - Vec3(0, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((box.max - Vec3(2, 1, 0)).norm(), 0.0, 1e-12);
  std::set<std::pair<long, long>> cells;
  for (const auto& p : pts) {
    EXPECT_NEAR(p.x() * 10.0, std::round(p.x() * 10.0), 1e-9);
    EXPECT_NEAR(p.y() * 10.0, std::round(p.y() * 10.0), 1e-9);
    EXPECT_EQ(p.z(), 0.0);
    cells.insert({std::lround(p.x() * 10.0), std::lround(p.y() * 10.0)});
  }
  EXPECT_EQ(cells.size(), 21u * 11u);  // all distinct
}

TEST(SurfaceSampler, SegmentsAndPointsCount) {
  WorldModel world;
  world.addLine("l", Vec3(0, 0, 0), Vec3(0, 0, 1.0));
  world.addPoint("p", Vec3(3, 3, 3));
  SampleOptions opt;
  opt.spacing_m = 0.25;
  opt.noise_sigma_m = 0.0;
  const PointList pts = sampleSurfaces(world, opt);
  ASSERT_EQ(pts.size(), 5u + 1u);
  for (int i = 0; i < 5; ++i) EXPECT_NEAR((pts[i] - Vec3(0, 0, 0.25 * i)).norm(), 0.0, 1e-12);
  EXPECT_EQ(pts[5], Vec3(3, 3, 3));
}

WorldModel mixedWorld() {
  WorldModel world;
  world.addBox("box", Vec3(0, 0, 0), Vec3(1.0, 0.6, 0.4), 20.0);
  world.addCrossedPlanes("x", Vec3(3, 0, 1), 1.0, 1.0, 10.0);
  world.addLine("pole", Vec3(-2, 0, 0), Vec3(-2, 0, 1.5));
  world.addPoint("pt", Vec3(0, 3, 1));
  return world;
}

TEST(SurfaceSampler, NoiseStaysNearTruth) {
  const WorldModel world = mixedWorld();
  SampleOptions opt;
  opt.spacing_m = 0.05;
  opt.noise_sigma_m = 0.01;
  opt.outlier_fraction = 0.0;
  const PointList pts = sampleSurfaces(world, opt);
  ASSERT_GT(pts.size(), 500u);
  double sum_sq = 0.0;
  size_t beyond_3sigma = 0;
  for (const auto& p : pts) {
    const double d = world.distanceToTruth(p);
    // Rectangles (the bulk) have 1D noise along the normal, segments and points 3D
    // noise (norm < 5σ·√3 too, P < 1e-6 per point); 5σ in 1D has P < 6e-7.
    EXPECT_LT(d, 5.0 * std::sqrt(3.0) * opt.noise_sigma_m);
    if (d > 3.0 * opt.noise_sigma_m) ++beyond_3sigma;
    sum_sq += d * d;
  }
  // |N(0,1)| > 3 has P = 0.27 %; allow 1 %.
  EXPECT_LT(beyond_3sigma, pts.size() / 100);
  // And it is noisy at all: RMS distance is a sizeable part of sigma.
  const double rms = std::sqrt(sum_sq / pts.size());
  EXPECT_GT(rms, 0.3 * opt.noise_sigma_m);
  EXPECT_LT(rms, 1.5 * opt.noise_sigma_m);
}

TEST(SurfaceSampler, RectNoiseIsAlongNormal) {
  WorldModel world;
  world.addPlane(tiltedRect());
  SampleOptions opt;
  opt.spacing_m = 0.1;
  opt.noise_sigma_m = 0.02;
  const PointList pts = sampleSurfaces(world, opt);
  const Rect& r = world.rects()[0];
  int beyond_5sigma = 0;  // P(|N(0,1)| > 5) < 6e-7 per point
  for (const auto& p : pts) {
    // In-plane coordinates stay on the grid inside the rectangle.
    const double s = (p - r.corner).dot(r.edge_u) / r.edge_u.squaredNorm();
    const double t = (p - r.corner).dot(r.edge_v) / r.edge_v.squaredNorm();
    EXPECT_GE(s, -1e-9);
    EXPECT_LE(s, 1.0 + 1e-9);
    EXPECT_GE(t, -1e-9);
    EXPECT_LE(t, 1.0 + 1e-9);
    if (std::abs((p - r.corner).dot(r.normal())) > 5.0 * opt.noise_sigma_m) ++beyond_5sigma;
  }
  EXPECT_EQ(beyond_5sigma, 0);
}

TEST(SurfaceSampler, DeterministicAndSeedSensitive) {
  const WorldModel world = mixedWorld();
  SampleOptions opt;
  opt.spacing_m = 0.1;
  opt.outlier_fraction = 0.05;
  const PointList a = sampleSurfaces(world, opt);
  const PointList b = sampleSurfaces(world, opt);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]);
  opt.seed = 2;
  const PointList c = sampleSurfaces(world, opt);
  ASSERT_EQ(a.size(), c.size());
  size_t differ = 0;
  for (size_t i = 0; i < a.size(); ++i) differ += (a[i] != c[i]) ? 1 : 0;
  EXPECT_GT(differ, a.size() / 2);
}

TEST(SurfaceSampler, OutliersCountAndBox) {
  const WorldModel world = mixedWorld();
  SampleOptions opt;
  opt.spacing_m = 0.1;
  opt.noise_sigma_m = 0.0;
  const PointList clean = sampleSurfaces(world, opt);
  opt.outlier_fraction = 0.1;
  opt.outlier_margin_m = 0.5;
  const PointList dirty = sampleSurfaces(world, opt);
  const size_t expected = static_cast<size_t>(std::llround(0.1 * clean.size()));
  ASSERT_EQ(dirty.size(), clean.size() + expected);
  // The sampled part is unchanged (noise 0) and the outliers lie in the grown box.
  for (size_t i = 0; i < clean.size(); ++i) EXPECT_EQ(clean[i], dirty[i]);
  const Aabb box = boundingBox(clean);
  size_t far = 0;
  for (size_t i = clean.size(); i < dirty.size(); ++i) {
    EXPECT_TRUE((dirty[i].array() >= box.min.array() - 0.5 - 1e-12).all());
    EXPECT_TRUE((dirty[i].array() <= box.max.array() + 0.5 + 1e-12).all());
    if (world.distanceToTruth(dirty[i]) > 0.05) ++far;
  }
  EXPECT_GT(far, expected / 2);  // uniform outliers are mostly off the surfaces
}

TEST(SurfaceSampler, EmptyWorldGivesNoPoints) {
  SampleOptions opt;
  opt.outlier_fraction = 0.5;
  EXPECT_TRUE(sampleSurfaces(WorldModel{}, opt).empty());
}

TEST(SurfaceSampler, BadOptionsThrowNamingTheField) {
  auto message = [](const SampleOptions& o) {
    try {
      o.validate();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  SampleOptions o;
  EXPECT_NO_THROW(o.validate());
  o.spacing_m = 0.0;
  EXPECT_NE(message(o).find("spacing_m"), std::string::npos);
  o = SampleOptions{};
  o.noise_sigma_m = -0.1;
  EXPECT_NE(message(o).find("noise_sigma_m"), std::string::npos);
  o = SampleOptions{};
  o.outlier_fraction = 1.0;
  EXPECT_NE(message(o).find("outlier_fraction"), std::string::npos);
  o.outlier_fraction = -0.01;
  EXPECT_NE(message(o).find("outlier_fraction"), std::string::npos);
  o = SampleOptions{};
  o.outlier_margin_m = -1.0;
  EXPECT_NE(message(o).find("outlier_margin_m"), std::string::npos);
  EXPECT_NE(message(o).find("sample:"), std::string::npos);
  EXPECT_THROW(sampleSurfaces(mixedWorld(), o), InputError);
}

}  // namespace
}  // namespace uavip::sim
