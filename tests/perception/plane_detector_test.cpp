#include "uavip/perception/plane_detector.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"

namespace uavip::perception {
namespace {

constexpr double kPi = 3.14159265358979323846;

double angleDeg(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / kPi;
}

/// Grid of (nu × nv) points c + i·step·u + j·step·v (centred on c), each moved by
/// isotropic Gaussian noise sigma.
void addPatch(PointList& out, const Vec3& c, const Vec3& u, const Vec3& v, int nu, int nv,
              double step, double sigma, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, sigma);
  const double hu = 0.5 * (nu - 1) * step;
  const double hv = 0.5 * (nv - 1) * step;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const Vec3 p = c + (i * step - hu) * u + (j * step - hv) * v;
      out.push_back(sigma > 0.0 ? Vec3(p + Vec3(noise(rng), noise(rng), noise(rng))) : p);
    }
  }
}

/// Surface of an axis-aligned cube (edge 2·half, grid step), every grid point once.
PointList cube(const Vec3& center, double half, double step, double sigma, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  const int n = static_cast<int>(std::lround(2.0 * half / step));
  PointList pts;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      for (int k = 0; k <= n; ++k) {
        const bool on_surface = i == 0 || i == n || j == 0 || j == n || k == 0 || k == n;
        if (!on_surface) continue;
        const Vec3 p = center + Vec3(i * step - half, j * step - half, k * step - half);
        pts.push_back(p + Vec3(noise(rng), noise(rng), noise(rng)));
      }
    }
  }
  return pts;
}

/// The area of the outline of an l × w rectangle sampled up to its edges: at least 95 %
/// of it, at most the rectangle grown by one cell (the outline is traced on whole
/// cells centred on the points' extent: at most half a cell past them on each side).
void expectOutlineArea(double area, double l, double w, double cell) {
  EXPECT_GE(area, 0.95 * l * w);
  EXPECT_LE(area, (l + cell) * (w + cell) + 1e-6);
}

/// Checks the invariants of one surface: unit normal, axes, boundary on the plane
/// and counter-clockwise seen from +normal, areas, centroid.
void expectConsistent(const Surface& s, double cell) {
  EXPECT_NEAR(s.plane.normal.norm(), 1.0, 1e-9);
  EXPECT_NEAR(s.axis_u.norm(), 1.0, 1e-9);
  EXPECT_NEAR(s.axis_v.norm(), 1.0, 1e-9);
  EXPECT_LT((s.axis_u.cross(s.axis_v) - s.plane.normal).norm(), 1e-9);
  ASSERT_GE(s.boundary.size(), 3u);
  Vec3 vector_area = Vec3::Zero();
  for (std::size_t i = 0; i < s.boundary.size(); ++i) {
    EXPECT_LT(std::abs(s.plane.signedDistance(s.boundary[i])), 1e-5);
    vector_area += s.boundary[i].cross(s.boundary[(i + 1) % s.boundary.size()]);
  }
  EXPECT_GT(vector_area.dot(s.plane.normal), 0.0) << "boundary not counter-clockwise";
  double holes = 0.0;  // openings run clockwise and lie on the plane too
  for (const auto& h : s.holes) {
    Vec3 hole_area = Vec3::Zero();
    for (std::size_t i = 0; i < h.size(); ++i) {
      EXPECT_LT(std::abs(s.plane.signedDistance(h[i])), 1e-5);
      hole_area += h[i].cross(h[(i + 1) % h.size()]);
    }
    EXPECT_LT(hole_area.dot(s.plane.normal), 0.0) << "hole not clockwise";
    holes += 0.5 * hole_area.norm();
  }
  EXPECT_NEAR(0.5 * vector_area.norm() - holes, s.area_m2, 1e-6 * std::max(1.0, s.area_m2));
  // Occupied cells: never more cells than points, never (much) more than the hull.
  EXPECT_LE(s.density_area_m2, static_cast<double>(s.inliers.size()) * cell * cell + 1e-9);
  EXPECT_LE(s.density_area_m2,
            s.area_m2 + 4.0 * cell * std::sqrt(std::max(s.area_m2, 0.0)) * 2.0 + 1e-9);
  Vec3 mean = Vec3::Zero();
  for (const auto& p : s.inliers) mean += p;
  mean /= static_cast<double>(s.inliers.size());
  EXPECT_LT((mean - s.centroid).norm(), 1e-9);
  EXPECT_LT(std::abs(s.plane.signedDistance(s.centroid)), 1e-9);
}

TEST(PlaneDetector, RecoversAnInclinedPlane) {
  // 0.3x + 0.2y + z - 1 = 0, 4 m x 4 m at 10 cm, 1 cm noise.
  const Vec3 n_true = Vec3(0.3, 0.2, 1.0).normalized();
  const double d_true = -1.0 / Vec3(0.3, 0.2, 1.0).norm();
  const Vec3 c = Vec3(0.0, 0.0, 1.0);  // on the plane
  const Vec3 u = n_true.cross(Vec3::UnitX()).normalized();
  const Vec3 v = n_true.cross(u);
  std::mt19937 rng(11);
  PointList cloud;
  addPatch(cloud, c, u, v, 41, 41, 0.1, 0.01, rng);

  PlaneDetectionOptions o;
  o.cell_size_m = 0.1;
  o.viewpoint = Vec3(0.0, 0.0, 10.0);  // above the plane: the normal points up
  const auto r = detectPlanes(cloud, o);
  ASSERT_EQ(r.surfaces.size(), 1u);
  const Surface& s = r.surfaces[0];
  EXPECT_EQ(s.id, 0);
  EXPECT_LT(angleDeg(s.plane.normal, n_true), 1.0);
  EXPECT_NEAR(s.plane.offset, d_true, 0.01);
  EXPECT_GE(s.inliers.size(), 41u * 41u - 2u);
  EXPECT_EQ(s.inliers.size() + r.remaining.size(), cloud.size());
  expectOutlineArea(s.area_m2, 4.0, 4.0, o.cell_size_m);
  expectConsistent(s, o.cell_size_m);
  // The paper's convex hull (perception.boundary: convex) of the same points.
  PlaneDetectionOptions convex = o;
  convex.boundary = "convex";
  const auto rc = detectPlanes(cloud, convex);
  ASSERT_EQ(rc.surfaces.size(), 1u);
  EXPECT_NEAR(rc.surfaces[0].area_m2, 16.0, 16.0 * 0.05);
  EXPECT_TRUE(rc.surfaces[0].holes.empty());
  // The first principal axis of a square is ambiguous; it must lie in the plane.
  EXPECT_NEAR(angleDeg(s.axis_u, n_true), 90.0, 1.0);
}

TEST(PlaneDetector, LoneWallPointsTowardTheViewpoint) {
  // Wall x = 5 (6 m along y, 3 m tall), viewpoint at the origin: normal -x, offset 5.
  std::mt19937 rng(12);
  PointList cloud;
  addPatch(cloud, Vec3(5.0, 1.0, 1.5), Vec3::UnitY(), Vec3::UnitZ(), 61, 31, 0.1, 0.005, rng);
  PlaneDetectionOptions o;
  o.cell_size_m = 0.1;
  const auto r = detectPlanes(cloud, o);
  ASSERT_EQ(r.surfaces.size(), 1u);
  const Surface& s = r.surfaces[0];
  EXPECT_LT(angleDeg(s.plane.normal, -Vec3::UnitX()), 1.0);
  EXPECT_NEAR(s.plane.offset, 5.0, 0.01);
  // Principal axis of a 6 x 3 wall: along y.
  EXPECT_LT(angleDeg(s.axis_u, Vec3::UnitY()), 2.0);
  expectOutlineArea(s.area_m2, 6.0, 3.0, o.cell_size_m);
  expectConsistent(s, o.cell_size_m);

  // Seen from the other side, the same wall faces +x.
  o.viewpoint = Vec3(10.0, 0.0, 0.0);
  const auto r2 = detectPlanes(cloud, o);
  ASSERT_EQ(r2.surfaces.size(), 1u);
  EXPECT_LT(angleDeg(r2.surfaces[0].plane.normal, Vec3::UnitX()), 1.0);
  EXPECT_NEAR(r2.surfaces[0].plane.offset, -5.0, 0.01);
}

TEST(PlaneDetector, NormalPointsAwayFromAnEnclosingSide) {
  // Wall y = 0 (4 m x 4 m) with a parallel 4 m x 4 m wall 2 m behind it (y = -2), as
  // two faces of a closed box: free space is +y, even with the viewpoint behind.
  std::mt19937 rng(15);
  PointList cloud;
  addPatch(cloud, Vec3(0, 0, 0), Vec3::UnitX(), Vec3::UnitZ(), 41, 41, 0.1, 0.003, rng);
  addPatch(cloud, Vec3(0, -2, 0), Vec3::UnitX(), Vec3::UnitZ(), 41, 41, 0.1, 0.003, rng);
  PlaneDetectionOptions o;
  o.cell_size_m = 0.1;
  o.viewpoint = Vec3(2.0, -1.0, 2.0);  // between the walls
  const auto r = detectPlanes(cloud, o);
  ASSERT_EQ(r.surfaces.size(), 2u);
  for (const auto& s : r.surfaces) {
    // each wall's normal points away from the other wall (outward of the slab)
    const double y = s.centroid.y();
    EXPECT_LT(angleDeg(s.plane.normal, Vec3(0.0, y > -1.0 ? 1.0 : -1.0, 0.0)), 1.0) << y;
  }
}

TEST(PlaneDetector, ClutterOnOneSideDoesNotFlipAGround) {
  // Ground z = 0 (6 m x 6 m) with a 1 m block standing on it: the block covers only
  // part of the ground, so the side above is not enclosed and the viewpoint above
  // decides (counting points per side would point the ground down).
  std::mt19937 rng(16);
  PointList cloud;
  addPatch(cloud, Vec3(0, 0, 0), Vec3::UnitX(), Vec3::UnitY(), 61, 61, 0.1, 0.003, rng);
  for (int i = 0; i < 11; ++i) {
    for (int j = 0; j < 11; ++j) {
      for (int k = 4; k < 15; ++k) cloud.emplace_back(2.0 + 0.1 * i, 2.0 + 0.1 * j, 0.1 * k);
    }
  }
  PlaneDetectionOptions o;
  o.cell_size_m = 0.1;
  o.viewpoint = Vec3(3.0, 3.0, 3.0);
  const auto r = detectPlanes(cloud, o);
  ASSERT_GE(r.surfaces.size(), 1u);
  EXPECT_LT(angleDeg(r.surfaces[0].plane.normal, Vec3::UnitZ()), 1.0);
  o.viewpoint = Vec3(3.0, 3.0, -3.0);  // the viewpoint decides: below
  const auto r2 = detectPlanes(cloud, o);
  ASSERT_GE(r2.surfaces.size(), 1u);
  EXPECT_LT(angleDeg(r2.surfaces[0].plane.normal, -Vec3::UnitZ()), 1.0);
}

TEST(PlaneDetector, ScannedCloudFacesTheStationsThatSawIt) {
  // The bridge as scanned from under the deck: ground z = 0 and deck underside
  // z = 3.6 (8 m x 8 m each; the deck top is never seen), a station at 1.5 m
  // between them, plus a closed 2 m box on the ground whose far face (x = 5) the
  // station cannot see. Each plane is enclosed by the other within 6 m, so the
  // enclosure rule alone points the ground down and the underside up (into the
  // deck); the stations' line of sight gives ground up, underside down, and leaves
  // the unseen box face to the enclosure rule (outward, +x).
  std::mt19937 rng(17);
  PointList cloud;
  addPatch(cloud, Vec3(0, 0, 0), Vec3::UnitX(), Vec3::UnitY(), 81, 81, 0.1, 0.003, rng);
  addPatch(cloud, Vec3(0, 0, 3.6), Vec3::UnitX(), Vec3::UnitY(), 81, 81, 0.1, 0.003, rng);
  PointList box = cube(Vec3(4.0, 0.0, 1.05), 1.0, 0.1, 0.003, 18);
  cloud.insert(cloud.end(), box.begin(), box.end());
  PlaneDetectionOptions o;
  o.cell_size_m = 0.1;
  o.viewpoint = Vec3(-2.0, 0.5, 1.5);
  o.viewpoints_scanned = true;
  const auto r = detectPlanes(cloud, o);
  int checked = 0;
  for (const auto& s : r.surfaces) {
    const Vec3& c = s.centroid;
    if (std::abs(c.z()) < 0.1 && s.area_m2 > 30.0) {  // not the box's bottom (z = 0.05)
      EXPECT_LT(angleDeg(s.plane.normal, Vec3::UnitZ()), 1.0) << "ground";
      ++checked;
    } else if (std::abs(c.z() - 3.6) < 0.1 && s.area_m2 > 30.0) {
      EXPECT_LT(angleDeg(s.plane.normal, -Vec3::UnitZ()), 1.0) << "underside";
      ++checked;
    } else if (std::abs(c.x() - 5.0) < 0.1) {
      EXPECT_LT(angleDeg(s.plane.normal, Vec3::UnitX()), 1.0) << "box face the station cannot see";
      ++checked;
    } else if (std::abs(c.x() - 3.0) < 0.1) {
      EXPECT_LT(angleDeg(s.plane.normal, -Vec3::UnitX()), 1.0) << "box face toward the station";
      ++checked;
    }
  }
  EXPECT_EQ(checked, 4);
  // Without the scanned flag the enclosure rule turns both large planes inward.
  o.viewpoints_scanned = false;
  const auto old = detectPlanes(cloud, o);
  int old_checked = 0;
  for (const auto& s : old.surfaces) {
    if (s.area_m2 < 30.0) continue;
    const double up = std::abs(s.centroid.z()) < 0.1 ? -1.0 : 1.0;  // ground down, underside up
    EXPECT_LT(angleDeg(s.plane.normal, up * Vec3::UnitZ()), 1.0) << s.centroid.z();
    ++old_checked;
  }
  EXPECT_EQ(old_checked, 2);
  // No ray longer than tuning.sight_range_m is cast: at 1 m, shorter than every ray
  // from the station here, the line of sight decides nothing and the enclosure rule
  // turns both large planes inward again.
  o.viewpoints_scanned = true;
  o.tuning.sight_range_m = 1.0;
  int short_checked = 0;
  for (const auto& s : detectPlanes(cloud, o).surfaces) {
    if (s.area_m2 < 30.0) continue;
    const double up = std::abs(s.centroid.z()) < 0.1 ? -1.0 : 1.0;
    EXPECT_LT(angleDeg(s.plane.normal, up * Vec3::UnitZ()), 1.0) << s.centroid.z();
    ++short_checked;
  }
  EXPECT_EQ(short_checked, 2);
}

TEST(PlaneDetector, TrimsAnIsolatedPatchOfTheSamePlane) {
  std::mt19937 rng(13);
  PointList cloud;
  addPatch(cloud, Vec3(0, 0, 0), Vec3::UnitX(), Vec3::UnitY(), 41, 41, 0.1, 0.005, rng);
  addPatch(cloud, Vec3(0, 0, 2.5), Vec3::UnitX(), Vec3::UnitY(), 41, 41, 0.1, 0.005, rng);
  const std::size_t before_patch = cloud.size();
  // 1 m x 1 m patch of the plane z = 0, 8 m away from the main 4 m x 4 m patch.
  addPatch(cloud, Vec3(8, 0, 0), Vec3::UnitX(), Vec3::UnitY(), 11, 11, 0.1, 0.005, rng);

  PlaneDetectionOptions o;
  o.cell_size_m = 0.1;
  const auto r = detectPlanes(cloud, o);
  ASSERT_EQ(r.surfaces.size(), 2u);
  int ground = -1;
  for (int i = 0; i < 2; ++i) {
    const auto& s = r.surfaces[static_cast<std::size_t>(i)];
    EXPECT_EQ(s.id, i);
    expectConsistent(s, o.cell_size_m);
    EXPECT_LT(
        std::min(angleDeg(s.plane.normal, Vec3::UnitZ()), angleDeg(s.plane.normal, -Vec3::UnitZ())),
        1.0);
    if (std::abs(s.centroid.z()) < 0.5) ground = i;
  }
  ASSERT_GE(ground, 0);
  const Surface& g = r.surfaces[static_cast<std::size_t>(ground)];
  for (const auto& b : g.boundary) {
    EXPECT_LT(std::abs(b.x()), 2.1) << "boundary reaches the isolated patch";
    EXPECT_LT(std::abs(b.y()), 2.1);
  }
  EXPECT_GE(g.inliers.size(), 41u * 41u - 2u);
  expectOutlineArea(g.area_m2, 4.0, 4.0, o.cell_size_m);
  // The isolated patch is returned to the remaining points (and rejected: 1 m² < 2 m²).
  EXPECT_GE(r.stats.trimmed_points, 121u);
  EXPECT_GE(r.stats.rejected_small, 1);
  std::size_t patch_left = 0;
  for (const auto& p : r.remaining) patch_left += p.x() > 6.0 ? 1 : 0;
  EXPECT_EQ(patch_left, cloud.size() - before_patch);
  EXPECT_EQ(r.remaining.size(),
            cloud.size() - r.surfaces[0].inliers.size() - r.surfaces[1].inliers.size());
  EXPECT_LE(r.remaining.size(), cloud.size() - before_patch + 4u);
  // The upper plate has the lower one behind it: its normal points up.
  const Surface& top = r.surfaces[static_cast<std::size_t>(1 - ground)];
  EXPECT_GT(top.plane.normal.z(), 0.99);
}

TEST(PlaneDetector, RejectsASmallPatch) {
  std::mt19937 rng(14);
  PointList cloud;
  addPatch(cloud, Vec3(1, 2, 3), Vec3::UnitX(), Vec3::UnitZ(), 21, 21, 0.05, 0.002, rng);  // 1 m²
  PlaneDetectionOptions o;  // min 2 m², cell 5 cm
  const auto r = detectPlanes(cloud, o);
  EXPECT_TRUE(r.surfaces.empty());
  EXPECT_EQ(r.remaining, cloud);
  EXPECT_GE(r.stats.rejected_small, 1);
  // The same patch passes a 0.5 m² threshold.
  o.min_area_m2 = 0.5;
  const auto r2 = detectPlanes(cloud, o);
  ASSERT_EQ(r2.surfaces.size(), 1u);
  expectOutlineArea(r2.surfaces[0].area_m2, 1.0, 1.0, o.cell_size_m);
}

TEST(PlaneDetector, ManySmallCoplanarPatchesDoNotHideALargerPlane) {
  // Twenty 1 m² patches on z = 0 (2420 points: RANSAC proposes this plane first) and
  // one 4 m x 4 m plate (1681 points) at z = 5.
  std::mt19937 rng(16);
  PointList cloud;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 4; ++j) {
      addPatch(cloud, Vec3(3.0 * i, 3.0 * j, 0.0), Vec3::UnitX(), Vec3::UnitY(), 11, 11, 0.1, 0.003,
               rng);
    }
  }
  addPatch(cloud, Vec3(6.0, 4.5, 5.0), Vec3::UnitX(), Vec3::UnitY(), 41, 41, 0.1, 0.003, rng);
  PlaneDetectionOptions o;
  o.cell_size_m = 0.1;
  o.max_failures = 3;
  const auto r = detectPlanes(cloud, o);
  ASSERT_EQ(r.surfaces.size(), 1u);
  EXPECT_NEAR(r.surfaces[0].centroid.z(), 5.0, 0.01);
  expectOutlineArea(r.surfaces[0].area_m2, 4.0, 4.0, o.cell_size_m);
  EXPECT_GE(r.stats.rejected_small, 1);
  EXPECT_EQ(r.remaining.size(), cloud.size() - r.surfaces[0].inliers.size());
}

TEST(PlaneDetector, FloatingCubeGivesSixOutwardFaces) {
  const Vec3 center(10.0, -3.0, 5.0);
  const PointList cloud = cube(center, 1.0, 0.05, 0.005, 21);
  PlaneDetectionOptions o;  // paper defaults: 20 cm, 200 iterations, 2 m², 5 cm cells
  const auto r = detectPlanes(cloud, o);
  ASSERT_EQ(r.surfaces.size(), 6u);
  std::vector<int> hits(6, 0);
  std::size_t in_surfaces = 0;
  for (const auto& s : r.surfaces) {
    expectConsistent(s, o.cell_size_m);
    in_surfaces += s.inliers.size();
    // Outward: the normal points from the cube centre to the face.
    const Vec3 out = s.centroid - center;
    EXPECT_GT(s.plane.normal.dot(out), 0.9) << "face at " << s.centroid.transpose();
    EXPECT_NEAR(out.norm(), 1.0, 0.1);
    EXPECT_NEAR(s.area_m2, 4.0, 0.6);
    EXPECT_NEAR(s.density_area_m2, 4.0, 0.6);
    for (int a = 0; a < 3; ++a) {
      for (int sign = 0; sign < 2; ++sign) {
        const Vec3 axis = (sign == 0 ? 1.0 : -1.0) * Vec3::Unit(a);
        if (angleDeg(s.plane.normal, axis) < 2.0) ++hits[static_cast<std::size_t>(2 * a + sign)];
      }
    }
  }
  for (int h : hits) EXPECT_EQ(h, 1);
  EXPECT_EQ(in_surfaces + r.remaining.size(), cloud.size());
  EXPECT_GE(in_surfaces, cloud.size() * 95 / 100);
}

TEST(PlaneDetector, WithoutASensorABuildingFacesOutAndGroundAndRoofFaceUp) {
  // An airborne-like cloud: a 12 × 8 × 6 m building box standing on a 40 × 40 m
  // ground, sparse (0.3 m), no sensor position. The building's inside sees its other
  // walls; the outside, the roof's sky and the ground's sky are open.
  std::mt19937 rng(5);
  PointList cloud;
  const Vec3 c(3.0, -2.0, 0.0);
  addPatch(cloud, Vec3(0, 0, 0), Vec3::UnitX(), Vec3::UnitY(), 134, 134, 0.3, 0.02, rng);  // ground
  addPatch(cloud, c + Vec3(0, 0, 6), Vec3::UnitX(), Vec3::UnitY(), 40, 27, 0.3, 0.02, rng);  // roof
  addPatch(cloud, c + Vec3(6, 0, 3), Vec3::UnitY(), Vec3::UnitZ(), 27, 20, 0.3, 0.02,
           rng);  // east wall
  addPatch(cloud, c + Vec3(-6, 0, 3), Vec3::UnitY(), Vec3::UnitZ(), 27, 20, 0.3, 0.02,
           rng);  // west wall
  addPatch(cloud, c + Vec3(0, 4, 3), Vec3::UnitX(), Vec3::UnitZ(), 40, 20, 0.3, 0.02,
           rng);  // north wall
  addPatch(cloud, c + Vec3(0, -4, 3), Vec3::UnitX(), Vec3::UnitZ(), 40, 20, 0.3, 0.02,
           rng);  // south wall
  PlaneDetectionOptions o;
  o.viewpoint_known = false;
  o.viewpoint = c + Vec3(0, 0, 3);  // a wrong hint inside the building must not matter
  o.cluster_tolerance_m = 0.9;
  o.cell_size_m = 0.3;
  o.open_voxel_m = 0.6;
  const auto r = detectPlanes(cloud, o);
  ASSERT_GE(r.surfaces.size(), 6u);
  int found = 0;
  for (const auto& s : r.surfaces) {
    const Vec3& n = s.plane.normal;
    if (std::abs(n.z()) > 0.9) {
      EXPECT_GT(n.z(), 0.9) << "level surface at z " << s.centroid.z() << " faces down";
      ++found;
    } else {
      // A wall faces away from the building's axis.
      const Vec3 out = s.centroid - Vec3(c.x(), c.y(), s.centroid.z());
      EXPECT_GT(n.dot(out), 0.0) << "wall at " << s.centroid.transpose() << " faces in";
      ++found;
    }
  }
  EXPECT_GE(found, 6);
}

TEST(PlaneDetector, DeterministicForTheSameInput) {
  const PointList cloud = cube(Vec3(0, 0, 0), 1.0, 0.1, 0.005, 22);
  PlaneDetectionOptions o;
  o.cell_size_m = 0.1;
  o.min_area_m2 = 1.0;
  const auto a = detectPlanes(cloud, o);
  const auto b = detectPlanes(cloud, o);
  ASSERT_EQ(a.surfaces.size(), b.surfaces.size());
  ASSERT_FALSE(a.surfaces.empty());
  for (std::size_t i = 0; i < a.surfaces.size(); ++i) {
    EXPECT_EQ(a.surfaces[i].plane.normal, b.surfaces[i].plane.normal);
    EXPECT_EQ(a.surfaces[i].plane.offset, b.surfaces[i].plane.offset);
    EXPECT_EQ(a.surfaces[i].inliers, b.surfaces[i].inliers);
    EXPECT_EQ(a.surfaces[i].boundary, b.surfaces[i].boundary);
  }
  EXPECT_EQ(a.remaining, b.remaining);
  // Another seed samples differently but finds the same six faces.
  o.seed = 7;
  const auto c = detectPlanes(cloud, o);
  EXPECT_EQ(c.surfaces.size(), 6u);
}

TEST(PlaneDetector, GuessingTheNextStepAheadGivesTheOneThreadSurfaces) {
  // Accepted and rejected candidates in turn: a floating cube (six faces) over small
  // coplanar patches that RANSAC proposes and stage 4 rejects, so the guess taken
  // while a surface is built is both kept and thrown away. The reference is the
  // one-step-at-a-time detector.
  PointList cloud = cube(Vec3(0, 0, 3), 2.0, 0.1, 0.003, 31);
  std::mt19937 rng(32);
  for (int i = 0; i < 4; ++i) {
    addPatch(cloud, Vec3(-4.0 + 2.5 * i, -4.0, 0.0), Vec3::UnitX(), Vec3::UnitY(), 9, 9, 0.1, 0.003,
             rng);
  }
  PlaneDetectionOptions o;
  o.cell_size_m = 0.1;
  o.min_area_m2 = 2.0;
  o.threads = 1;
  const auto one = detectPlanes(cloud, o);
  o.threads = 2;
  const auto two = detectPlanes(cloud, o);
  ASSERT_EQ(one.surfaces.size(), 6u);
  EXPECT_GE(one.stats.rejected_small, 1);
  ASSERT_EQ(two.surfaces.size(), one.surfaces.size());
  for (std::size_t i = 0; i < one.surfaces.size(); ++i) {
    EXPECT_EQ(two.surfaces[i].plane.normal, one.surfaces[i].plane.normal);
    EXPECT_EQ(two.surfaces[i].plane.offset, one.surfaces[i].plane.offset);
    EXPECT_EQ(two.surfaces[i].inliers, one.surfaces[i].inliers);
    EXPECT_EQ(two.surfaces[i].boundary, one.surfaces[i].boundary);
    EXPECT_EQ(two.surfaces[i].area_m2, one.surfaces[i].area_m2);
  }
  EXPECT_EQ(two.remaining, one.remaining);
  EXPECT_EQ(two.stats.candidates, one.stats.candidates);
  EXPECT_EQ(two.stats.rejected_small, one.stats.rejected_small);
  EXPECT_EQ(two.stats.trimmed_points, one.stats.trimmed_points);
}

TEST(PlaneDetector, DegenerateInputsGiveNoSurface) {
  PlaneDetectionOptions o;
  EXPECT_TRUE(detectPlanes({}, o).surfaces.empty());
  const PointList one = {{1, 2, 3}};
  const auto r1 = detectPlanes(one, o);
  EXPECT_TRUE(r1.surfaces.empty());
  EXPECT_EQ(r1.remaining, one);
  const PointList same(50, Vec3(1, 1, 1));
  EXPECT_TRUE(detectPlanes(same, o).surfaces.empty());

  // An exact line, 10 m at 5 mm spacing.
  PointList line;
  for (int i = 0; i <= 2000; ++i) line.emplace_back(0.005 * i, 0.5 * 0.005 * i, 2.0);
  const auto rl = detectPlanes(line, o);
  EXPECT_TRUE(rl.surfaces.empty());
  EXPECT_EQ(rl.remaining.size(), line.size());

  // The same line with 5 mm noise: its density area (2001 × 25 cm² = 5 m²) passes
  // 2 m², but its hull (~10 m x 2 cm) does not.
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.005);
  for (auto& p : line) p += Vec3(noise(rng), noise(rng), noise(rng));
  const auto rn = detectPlanes(line, o);
  EXPECT_TRUE(rn.surfaces.empty());
  EXPECT_EQ(rn.remaining, line);
}

TEST(PlaneDetector, ValidatesOptions) {
  const PointList cloud = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const auto expectField = [&](const PlaneDetectionOptions& o, const std::string& field) {
    try {
      detectPlanes(cloud, o);
      ADD_FAILURE() << "expected InputError for " << field;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  PlaneDetectionOptions o;
  o.distance_threshold_m = 0.0;
  expectField(o, "distance_threshold_m");
  o = {};
  o.max_iterations = 0;
  expectField(o, "max_iterations");
  o = {};
  o.min_area_m2 = -1.0;
  expectField(o, "min_area_m2");
  o = {};
  o.cluster_tolerance_m = -0.1;
  expectField(o, "cluster_tolerance_m");
  o = {};
  o.cell_size_m = std::nan("");
  expectField(o, "area_cell_m");  // the key a config file sets it with
  o = {};
  o.threads = -1;
  expectField(o, "threads");
  o = {};
  o.tuning.band_floor = 1.5;
  expectField(o, "tuning: band_floor");
  o = {};
  o.tuning.sight_rays = 0;
  expectField(o, "tuning: sight_rays");
  o = {};
  o.tuning.sight_range_m = -30.0;
  expectField(o, "tuning: sight_range_m");
  o = {};
  o.max_failures = 0;
  expectField(o, "max_failures");
}

}  // namespace
}  // namespace uavip::perception
