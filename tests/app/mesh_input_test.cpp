// A mesh of a scenario's primitives, written by the test as STL and OBJ, read and
// detected: the same planes as the simulator's ground truth (io/mesh_reader.h).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "../io/mesh_files.h"
#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/io/cloud_io.h"

namespace uavip::app {
namespace {

namespace fs = std::filesystem;

/// The scenario's rectangles as two triangles each.
mesh_test::Triangles rectTriangles(const sim::WorldModel& world) {
  mesh_test::Triangles t;
  for (const sim::Rect& r : world.rects()) {
    const Vec3 a = r.corner, b = r.corner + r.edge_u, c = b + r.edge_v, d = r.corner + r.edge_v;
    t.push_back({a, b, c});
    t.push_back({a, c, d});
  }
  return t;
}

/// Detected surfaces on the true rectangle's plane (normal within 5°, offset and
/// centroid within 10 cm), as the scenario tests score the simulator's cloud.
int surfacesOn(const sim::Rect& rect, const Scene& scene, double* area) {
  int n = 0;
  for (const auto& s : scene.surfaces) {
    if (std::abs(s.plane.normal.dot(rect.normal())) < std::cos(5.0 * M_PI / 180.0)) continue;
    if (std::abs(s.plane.signedDistance(rect.center())) > 0.1) continue;
    if (rect.distance(s.centroid) > 0.1) continue;
    *area = s.area_m2;
    ++n;
  }
  return n;
}

TEST(MeshInput, CubeMeshIsDetectedIntoTheSimulatorsPlanes) {
  const Scenario scenario =
      loadScenario(std::string(UAVIP_SOURCE_DIR) + "/scenarios/single_cube.yaml");
  const fs::path d = fs::temp_directory_path() / "uavip_mesh_input_test";
  fs::create_directories(d);
  const mesh_test::Triangles tris = rectTriangles(scenario.world);
  ASSERT_EQ(tris.size(), 12u);
  mesh_test::writeStlBinary((d / "cube.stl").string(), tris);
  mesh_test::writeObj((d / "cube.obj").string(), tris);
  for (const char* name : {"cube.stl", "cube.obj"}) {
    SCOPED_TRACE(name);
    io::CloudReadOptions read;
    read.mesh_spacing_m = scenario.sample.spacing_m;  // the simulator's sampling, 5 cm
    const PointList raw = io::loadCloud((d / name).string(), read);
    const DetectResult det = detect(raw, scenario.config, measure(raw));
    EXPECT_EQ(det.scene.surfaces.size(), scenario.world.rects().size());
    for (const sim::Rect& rect : scenario.world.rects()) {
      SCOPED_TRACE(rect.name);
      double area = 0.0;
      EXPECT_EQ(surfacesOn(rect, det.scene, &area), 1);
      EXPECT_NEAR(area, rect.area(), 0.1 * rect.area());
    }
  }
}

}  // namespace
}  // namespace uavip::app
