// A mesh through the CLI as a user gives one: detect an STL, plan over it (the planes
// and the whole structure), validate the flight against the mesh's points; an empty
// mesh is one error line and exit 2.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../io/mesh_files.h"
#include "cli_runner.h"

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
