// Meshes in (io/mesh_reader.h through io::loadCloud): files written by the test, every
// sampled point checked against the triangles by brute force, densities against the
// areas, the glTF axes against the file's own.

#include "uavip/io/mesh_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "mesh_files.h"
#include "uavip/core/error.h"
#include "uavip/io/cloud_io.h"

namespace uavip::io {
namespace {

using mesh_test::Triangles;
namespace fs = std::filesystem;

/// A fresh folder for one test's files.
fs::path testDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("uavip_mesh_test_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

CloudReadOptions spacing(double s) {
  CloudReadOptions o;
  o.mesh_spacing_m = s;
  return o;
}

/// Every point lies on some triangle (exact distance, brute force).
void expectOnMesh(const PointList& points, const Triangles& tris, double tolerance = 1e-6) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double d = mesh_test::distanceToMesh(points[i], tris);
    ASSERT_LT(d, tolerance) << "point " << i << " (" << points[i].transpose()
                            << ") is off the mesh";
  }
}

const Vec3 kLo(0.0, 0.0, 1.0), kHi(1.0, 2.0, 4.0);

/// The box's six faces: points on each within rounding of area / s² (two triangles,
/// each rounded by less than one point).
void expectBoxDensity(const PointList& points, double s) {
  const double areas[3] = {(kHi.y() - kLo.y()) * (kHi.z() - kLo.z()),
                           (kHi.x() - kLo.x()) * (kHi.z() - kLo.z()),
                           (kHi.x() - kLo.x()) * (kHi.y() - kLo.y())};
  for (int axis = 0; axis < 3; ++axis) {
    for (const double at : {kLo[axis], kHi[axis]}) {
      std::size_t n = 0;
      for (const Vec3& p : points) n += std::abs(p[axis] - at) < 1e-9;
      // A point on an edge counts on two faces: the R2 points never fall on one.
      EXPECT_NEAR(static_cast<double>(n), areas[axis] / (s * s), 2.0)
          << "face axis " << axis << " at " << at;
    }
  }
}

TEST(MeshReader, BoxInEveryFormatIsSampledOnItsFacesByArea) {
  const fs::path d = testDir("box");
  const Triangles box = mesh_test::boxTriangles(kLo, kHi);
  mesh_test::writeStlAscii((d / "box_ascii.stl").string(), box);
  mesh_test::writeStlBinary((d / "box_binary.stl").string(), box);
  mesh_test::writeObj((d / "box.obj").string(), box);
  mesh_test::writePly((d / "box.ply").string(), box, true);
  const double s = 0.05;
  for (const char* name : {"box_ascii.stl", "box_binary.stl", "box.obj", "box.ply"}) {
    SCOPED_TRACE(name);
    CloudReadInfo info;
    const PointList points = loadCloud((d / name).string(), spacing(s), &info);
    ASSERT_TRUE(info.mesh.present);
    EXPECT_EQ(info.mesh.triangles, 12u);
    EXPECT_NEAR(info.mesh.area_m2, 2.0 * (2.0 * 3.0 + 1.0 * 3.0 + 1.0 * 2.0), 1e-9);
    EXPECT_EQ(info.mesh.spacing_m, s);
    expectOnMesh(points, box);
    expectBoxDensity(points, s);
  }
}

TEST(MeshReader, SmallTrianglesGiveAUniformDensity) {
  // A 2 m square cut into 7200 triangles of 5.6e-4 m² each, a quarter of s² at s = 0.05:
  // most get no point, some one; each quadrant's count is binomial about area / s².
  const fs::path d = testDir("grid");
  const Triangles plane =
      mesh_test::gridTriangles(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0.5), 60);
  mesh_test::writeStlBinary((d / "plane.stl").string(), plane);
  const double s = 0.05;
  const PointList points = loadCloud((d / "plane.stl").string(), spacing(s));
  expectOnMesh(points, plane);
  const double area = 2.0 * std::hypot(2.0, 0.5), expected = area / 4.0 / (s * s);
  std::size_t quadrant[4] = {0, 0, 0, 0};
  for (const Vec3& p : points) ++quadrant[(p.x() >= 1.0 ? 1 : 0) + (p.y() >= 1.0 ? 2 : 0)];
  for (const std::size_t n : quadrant)  // 5 sigma of the binomial (variance <= mean)
    EXPECT_NEAR(static_cast<double>(n), expected, 5.0 * std::sqrt(expected));
}

TEST(MeshReader, PointsSpreadEvenlyInsideOneLargeTriangle) {
  // One triangle split at its edge midpoints into four of equal area: each gets a quarter.
  const fs::path d = testDir("one");
  const Vec3 a(0, 0, 0), b(4, 0, 0), c(1, 3, 0);
  mesh_test::writeObj((d / "t.obj").string(), {{a, b, c}});
  const PointList points = loadCloud((d / "t.obj").string(), spacing(0.05));
  const Vec3 ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
  const Triangles parts = {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}};
  std::size_t counts[4] = {0, 0, 0, 0};
  for (const Vec3& p : points) {
    int nearest = 0;
    double best = 1e300;
    for (int k = 0; k < 4; ++k) {
      const double dist =
          mesh_test::pointTriangleDistance(p, parts[k][0], parts[k][1], parts[k][2]);
      if (dist < best) best = dist, nearest = k;
    }
    ++counts[nearest];
  }
  const double quarter = static_cast<double>(points.size()) / 4.0;
  for (const std::size_t n : counts)
    EXPECT_NEAR(static_cast<double>(n), quarter, 3.0 * std::sqrt(quarter));
}

TEST(MeshReader, SameMeshSamePoints) {
  const fs::path d = testDir("same");
  mesh_test::writeStlBinary((d / "box.stl").string(), mesh_test::boxTriangles(kLo, kHi));
  const PointList first = loadCloud((d / "box.stl").string(), spacing(0.04));
  const PointList second = loadCloud((d / "box.stl").string(), spacing(0.04));
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i) ASSERT_EQ(first[i], second[i]);
  // Another seed moves the points, not their number per face.
  TriangleMesh mesh = readMesh((d / "box.stl").string(), 1.0);
  MeshSampleOptions o;
  o.spacing_m = 0.04;
  o.seed = 7;
  const PointList other = sampleMesh(mesh, o, "box");
  EXPECT_NE(other.front(), first.front());
  expectBoxDensity(other, 0.04);
}

TEST(MeshReader, AutomaticSpacingFollowsTheMeshScale) {
  const fs::path d = testDir("auto");
  mesh_test::writeStlBinary((d / "box.stl").string(), mesh_test::boxTriangles(kLo, kHi));
  CloudReadInfo info;
  loadCloud((d / "box.stl").string(), {}, &info);
  // A 3 m object: extent / 200; no more than kAutoMeshPoints.
  EXPECT_DOUBLE_EQ(info.mesh.spacing_m, 3.0 / 200.0);
  EXPECT_EQ(info.mesh.spacing_source, "auto");
  EXPECT_DOUBLE_EQ(autoMeshSpacing(1e3, 500.0), kAutoMeshSpacingM);
  EXPECT_DOUBLE_EQ(autoMeshSpacing(1e6, 500.0), std::sqrt(1e6 / kAutoMeshPoints));
}

TEST(MeshReader, GltfIsTurnedFromYUpToZUp) {
  // A horizontal triangle 2 m up in glTF's frame (y up), its node moved 1 m further
  // up and 0.5 m along x: z = 3 once read.
  const fs::path d = testDir("gltf");
  const Vec3 up(0.5, 1, 0), a = Vec3(0, 2, 0) + up, b = Vec3(1, 2, 0) + up, c = Vec3(0, 2, -1) + up;
  mesh_test::writeGltf((d / "t.gltf").string(), {{a - up, b - up, c - up}}, up);
  CloudReadInfo info;
  const PointList points = loadCloud((d / "t.gltf").string(), spacing(0.02), &info);
  EXPECT_EQ(info.mesh.axes, "y up turned to z up");
  const auto zUp = [](const Vec3& p) { return Vec3(p.x(), -p.z(), p.y()); };
  ASSERT_GT(points.size(), 1000u);
  expectOnMesh(points, {{zUp(a), zUp(b), zUp(c)}});
  for (const Vec3& p : points) EXPECT_NEAR(p.z(), 3.0, 1e-6);
}

TEST(MeshReader, ScaleTurnsMillimetresIntoMetres) {
  const fs::path d = testDir("mm");
  mesh_test::writeStlBinary((d / "box.stl").string(),
                            mesh_test::boxTriangles(kLo * 1000.0, kHi * 1000.0));
  CloudReadOptions o = spacing(0.05);
  o.scale = 0.001;
  CloudReadInfo info;
  const PointList points = loadCloud((d / "box.stl").string(), o, &info);
  EXPECT_EQ(info.mesh.scale, 0.001);
  expectOnMesh(points, mesh_test::boxTriangles(kLo, kHi));
  expectBoxDensity(points, 0.05);  // spacing in metres, after the scale
}

TEST(MeshReader, PlyWithFacesIsAMeshWithoutACloud) {
  const fs::path d = testDir("ply");
  const Triangles box = mesh_test::boxTriangles(kLo, kHi);
  mesh_test::writePly((d / "faces.ply").string(), box, true);
  mesh_test::writePly((d / "cloud.ply").string(), box, false);
  EXPECT_TRUE(isMeshFile((d / "faces.ply").string()));
  EXPECT_FALSE(isMeshFile((d / "cloud.ply").string()));
  CloudReadInfo info;
  EXPECT_EQ(loadCloud((d / "cloud.ply").string(), {}, &info).size(), 36u);
  EXPECT_FALSE(info.mesh.present);
}

TEST(MeshReader, FarMeshIsRecentredLikeACloud) {
  const fs::path d = testDir("far");
  const Vec3 shift(20000.0, -30000.0, 0.0);
  mesh_test::writeStlBinary((d / "far.stl").string(),
                            mesh_test::boxTriangles(kLo + shift, kHi + shift));
  CloudReadInfo info;
  const PointList points = loadCloud((d / "far.stl").string(), spacing(0.05), &info);
  EXPECT_EQ(info.origin_m, recentringOrigin(kLo + shift, kHi + shift));
  EXPECT_GT(info.origin_m.norm(), 1e4);
  // Float rounding of the file (Assimp reads in single precision): about 2 mm at 30 km.
  expectOnMesh(points,
               mesh_test::boxTriangles(kLo + shift - info.origin_m, kHi + shift - info.origin_m),
               5e-3);
  // The triangles kept for safety are in the points' frame too.
  ASSERT_TRUE(info.triangles);
  EXPECT_EQ(info.triangles->triangles.size(), 12u);
  for (const Vec3& v : info.triangles->vertices) {
    const Vec3 file = v + info.origin_m;
    const Vec3 corner((file.x() < shift.x() + 0.5 * (kLo.x() + kHi.x()) ? kLo : kHi).x(),
                      (file.y() < shift.y() + 0.5 * (kLo.y() + kHi.y()) ? kLo : kHi).y(),
                      (file.z() < 0.5 * (kLo.z() + kHi.z()) ? kLo : kHi).z());
    EXPECT_LT((file - corner - shift).norm(), 5e-3) << v.transpose();
  }
}

void expectRefused(const std::string& path, const std::string& words) {
  try {
    loadCloud(path, spacing(0.05));
    ADD_FAILURE() << path << " was read";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find(words), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(MeshReader, BadMeshesAreRefusedNamingTheFile) {
  const fs::path d = testDir("bad");
  mesh_test::writeStlAscii((d / "empty.stl").string(), {});
  expectRefused((d / "empty.stl").string(), "mesh");
  { std::ofstream((d / "points.obj").string()) << "v 0 0 0\nv 1 0 0\nv 0 1 0\n"; }
  expectRefused((d / "points.obj").string(), "mesh");
  const Vec3 a(0, 0, 0), b(1, 1, 1);
  mesh_test::writeObj((d / "flat.obj").string(), {{a, b, 2.0 * b}, {a, a, b}});
  expectRefused((d / "flat.obj").string(), "degenerate");
  { std::ofstream((d / "junk.glb").string()) << "not a mesh at all"; }
  expectRefused((d / "junk.glb").string(), "cannot read the mesh");
  mesh_test::writeStlBinary((d / "big.stl").string(), mesh_test::boxTriangles(kLo, kHi * 1000.0));
  expectRefused((d / "big.stl").string(), "input.mesh_spacing_m >=");
  { std::ofstream((d / "x.unknownext").string()) << "1 2 3\n"; }
  expectRefused((d / "x.unknownext").string(), "unknown cloud extension");
}

TEST(MeshSampler, CorruptIndicesAndNonFiniteVerticesAreRefused) {
  TriangleMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  m.triangles = {{0, 1, 3}};
  EXPECT_THROW(sampleMesh(m, {}, "m"), InputError);
  m.triangles = {{0, 1, 2}};
  m.vertices[2] = Vec3(0, std::nan(""), 0);
  EXPECT_THROW(sampleMesh(m, {}, "m"), InputError);
  m.vertices[2] = Vec3(0, 1, 0);
  EXPECT_GT(sampleMesh(m, {0.01}, "m").size(), 0u);
}

}  // namespace
}  // namespace uavip::io
