// A mesh through the CLI as a user gives one: detect an STL, plan over it (the planes
// and the whole structure), validate the flight against the mesh's triangles (the
// clearance against brute force over every triangle; a leg too close refused); an
// empty mesh is one error line and exit 2.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../io/mesh_files.h"
#include "cli_runner.h"
#include "uavip/core/math.h"
#include "uavip/io/scene_json.h"
#include "uavip/world/collision_world.h"

namespace uavip::cli_test {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("uavip_mesh_cli_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(MeshCli, DetectPlanAndValidateAnStl) {
  const fs::path d = freshDir("cube");
  // The single_cube scenario's 3 m cube floating 1 m up, as a binary STL.
  mesh_test::writeStlBinary((d / "cube.stl").string(),
                            mesh_test::boxTriangles(Vec3(0, 0, 1), Vec3(3, 3, 4)));
  std::ofstream(d / "config.yaml") << "input: {mesh_spacing_m: 0.05}\n"
                                      "perception: {min_area_m2: 2.0}\n";
  const Result det =
      uavip("detect " + (d / "cube.stl").string() + " -c " + (d / "config.yaml").string() + " -o " +
            (d / "det").string() + " --no-views");
  ASSERT_EQ(det.code, 0) << det.out;
  EXPECT_NE(det.out.find("mesh (stl), 12 triangles"), std::string::npos) << det.out;
  const nlohmann::json scene = nlohmann::json::parse(slurp(d / "det" / "scene.json"));
  EXPECT_EQ(scene["surfaces"].size(), 6u);
  EXPECT_EQ(scene["input_read"]["source_kind"], "mesh");
  EXPECT_EQ(scene["input_read"]["mesh"]["format"], "stl");
  EXPECT_EQ(scene["input_read"]["mesh"]["triangles"], 12);
  EXPECT_EQ(scene["input_read"]["mesh"]["spacing_m"], 0.05);
  EXPECT_EQ(scene["safety"]["sha256"].get<std::string>().size(), 64u);

  // Planned into another folder: the scene goes with the mission.
  const Result plan = uavip("plan " + (d / "det" / "scene.json").string() + " --surface all -o " +
                            (d / "plan").string() + " --no-views");
  ASSERT_EQ(plan.code, 0) << plan.out;
  EXPECT_TRUE(fs::exists(d / "plan" / "scene.json"));
  const Result val = uavip("validate " + (d / "plan" / "mission.json").string());
  EXPECT_EQ(val.code, 0) << val.out;
  EXPECT_NE(val.out.find("sha256 checked"), std::string::npos) << val.out;

  const Result structure =
      uavip("plan " + (d / "det" / "scene.json").string() + " --cover structure -o " +
            (d / "structure").string() + " --no-views");
  EXPECT_EQ(structure.code, 0) << structure.out;
}

/// A tower like a statue's plinth and column: a 4 m pedestal, an octagonal column to
/// 9 m, an overhanging cap and a thin antenna (6 cm) on top, every corner rounded to
/// float as the STL holds it.
mesh_test::Triangles towerTriangles() {
  mesh_test::Triangles t = mesh_test::boxTriangles(Vec3(-2, -2, 0), Vec3(2, 2, 1));
  const double r = 1.2;
  for (int k = 0; k < 8; ++k) {
    const double a0 = k * kPi / 4, a1 = (k + 1) * kPi / 4;
    const Vec3 p0(r * std::cos(a0), r * std::sin(a0), 1), p1(r * std::cos(a1), r * std::sin(a1), 1);
    const Vec3 up(0, 0, 8);
    t.push_back({p0, p1, p1 + up});
    t.push_back({p0, p1 + up, p0 + up});
  }
  const mesh_test::Triangles cap =
      mesh_test::boxTriangles(Vec3(-1.8, -1.8, 9), Vec3(1.8, 1.8, 9.6));
  t.insert(t.end(), cap.begin(), cap.end());
  const mesh_test::Triangles mast =
      mesh_test::boxTriangles(Vec3(-0.03, -0.03, 9.6), Vec3(0.03, 0.03, 11.0));
  t.insert(t.end(), mast.begin(), mast.end());
  for (auto& tri : t)
    for (Vec3& p : tri) p = p.cast<float>().cast<double>();
  return t;
}

/// The waypoints of every sortie of a mission.json.
std::vector<std::vector<Vec3>> sortieWaypoints(const nlohmann::json& mission) {
  std::vector<std::vector<Vec3>> out;
  for (const auto& s : mission["flight"]["sorties"]) {
    std::vector<Vec3> w;
    for (const auto& p : s["waypoints"]) w.emplace_back(p[0], p[1], p[2]);
    out.push_back(std::move(w));
  }
  return out;
}

/// The number after `key` on the line that starts with `label` in `text` (NaN if none).
double numberAfter(const std::string& text, const std::string& label, const std::string& key) {
  const std::size_t line = text.find(label);
  if (line == std::string::npos) return std::nan("");
  const std::size_t end = text.find('\n', line);
  const std::size_t at = text.find(key, line);
  if (at == std::string::npos || at > end) return std::nan("");
  return std::stod(text.substr(at + key.size()));
}

TEST(MeshCli, StructureFlightKeepsItsClearanceFromEveryTriangle) {
  const fs::path d = freshDir("tower");
  const mesh_test::Triangles tower = towerTriangles();
  mesh_test::writeStlBinary((d / "tower.stl").string(), tower);
  std::ofstream(d / "config.yaml") << "input: {mesh_spacing_m: 0.1}\n";
  const Result det =
      uavip("detect " + (d / "tower.stl").string() + " -c " + (d / "config.yaml").string() +
            " -o " + (d / "det").string() + " --no-views");
  ASSERT_EQ(det.code, 0) << det.out;
  EXPECT_NE(det.out.find("the mesh's " + std::to_string(tower.size()) + " triangles"),
            std::string::npos)
      << det.out;
  const nlohmann::json scene = nlohmann::json::parse(slurp(d / "det" / "scene.json"));
  EXPECT_EQ(scene["safety"]["mesh"]["triangles"], tower.size());
  const Result plan = uavip("plan " + (d / "det" / "scene.json").string() +
                            " --cover structure -o " + (d / "plan").string() + " --no-views");
  ASSERT_EQ(plan.code, 0) << plan.out;
  EXPECT_TRUE(fs::exists(d / "plan" / "cloud_safety_mesh.stl"));  // travels with the scene
  const nlohmann::json mission = nlohmann::json::parse(slurp(d / "plan" / "mission.json"));
  const double clearance = mission["inflation_radius_m"].get<double>();
  // No sparse-cloud allowance: the plan keeps the UAV's own radius from the triangles.
  EXPECT_DOUBLE_EQ(mission["safety_clearance_m"].get<double>(), clearance);

  const Result val = uavip("validate " + (d / "plan" / "mission.json").string());
  ASSERT_EQ(val.code, 0) << val.out;
  EXPECT_NE(val.out.find("mesh of " + std::to_string(tower.size()) + " triangles"),
            std::string::npos)
      << val.out;
  const auto sorties = sortieWaypoints(mission);
  ASSERT_FALSE(sorties.empty());
  for (std::size_t i = 0; i < sorties.size(); ++i) {
    const double brute = mesh_test::pathDistanceToMesh(sorties[i], tower);
    const double reported = numberAfter(val.out, "sortie " + std::to_string(i + 1) + ":",
                                        "to the input mesh's triangles ");
    EXPECT_NEAR(reported, brute, 1e-6) << "sortie " << i + 1 << "\n" << val.out;
    EXPECT_GE(brute, clearance - 1e-9);
  }

  // A leg that passes the antenna closer than the clearance is refused, its distance
  // the brute-force one.
  nlohmann::json bad = mission;
  const Vec3 by(0.03 + 0.5 * clearance, -1.0, 10.5), to(0.03 + 0.5 * clearance, 1.0, 10.5);
  bad["flight"]["sorties"][0]["waypoints"] =
      nlohmann::json::array({{by.x(), by.y(), by.z()}, {to.x(), to.y(), to.z()}});
  bad["flight"]["sorties"][0]["stops"] = nlohmann::json::array();
  std::ofstream(d / "plan" / "bad.json") << bad.dump();
  const Result refused = uavip("validate " + (d / "plan" / "bad.json").string());
  EXPECT_EQ(refused.code, 3) << refused.out;
  const double leg = mesh_test::pathDistanceToMesh({by, to}, tower);
  EXPECT_NEAR(leg, 0.5 * clearance, 1e-6);
  // The world may name the antenna's obstacle solid, never farther than the triangles.
  EXPECT_LE(numberAfter(refused.out, "VIOLATION: segment 0", "comes "), leg + 1e-3) << refused.out;
  // The scene's copy of the triangles, measured exactly by the collision world.
  const Scene copied = io::loadScene((d / "plan" / "scene.json").string());
  ASSERT_TRUE(copied.safety && copied.safety->mesh);
  EXPECT_EQ(copied.safety->mesh->triangles.size(), tower.size());
  const world::CollisionWorld triangles = world::CollisionWorld::fromMesh(copied.safety->mesh);
  const world::Proximity p = triangles.proximity(by, to, clearance);
  EXPECT_NEAR(p.distance_m, leg, 1e-9);
  EXPECT_EQ(triangles.objects()[static_cast<std::size_t>(p.object)].name(), "mesh triangle");
}

TEST(MeshCli, EmptyMeshIsExit2WithOneLine) {
  const fs::path d = freshDir("empty");
  mesh_test::writeStlAscii((d / "empty.stl").string(), {});
  const Result r = uavip("detect " + (d / "empty.stl").string() + " -o " + (d / "out").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("empty.stl"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << r.out;  // one line
}

}  // namespace
}  // namespace uavip::cli_test
