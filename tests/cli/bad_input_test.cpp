// The bad-input table: hostile and broken inputs to every command, each
// must give exit 2 (3 where a mission is refused), exactly one line starting
// "uavip: error:" (or "uavip: " for exit 3) that names the file, key or value, and
// must leave the previous results in the output folder byte for byte.

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.h"

namespace {

namespace fs = std::filesystem;
using uavip::cli_test::Result;
using uavip::cli_test::slurp;
using uavip::cli_test::uavip;

struct Case {
  const char* name;
  std::string args;  ///< after `uavip -q`; $D is the fixture folder
  int code;
  std::string fragment;  ///< must appear in the one line
};

class BadInput : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("uavip_bad_input_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "scans");
    // A good result to keep: run writes scene, mission and views into prev/.
    good_ = uavip("-q run " + std::string(UAVIP_SOURCE_DIR) + "/scenarios/single_plane.yaml -o " +
                  (dir_ / "prev").string());
    for (const char* f :
         {"scene.json", "mission.json", "cloud_clean.pcd", "overview.png", "path.obj"})
      before_.push_back(slurp(dir_ / "prev" / f));
    writeFixtures();
    // Scenes that are valid JSON but wrong: an id beyond int, an id used twice, a negative area.
    const std::string scene = slurp(dir_ / "prev/scene.json");
    if (!scene.empty()) {
      auto j = nlohmann::json::parse(scene);
      auto big = j;
      big["surfaces"][0]["id"] = 4294967296LL;
      write("scene_bigid.json", big.dump());
      auto twice = j;
      twice["surfaces"].push_back(j["surfaces"][0]);
      write("scene_twice.json", twice.dump());
      auto negative = j;
      negative["surfaces"][0]["area_m2"] = -3.0;
      write("scene_negative.json", negative.dump());
      // Edits files for the wall, fingerprinted from this scene.
      const auto& c = j["surfaces"][0]["centroid"];
      const auto& n = j["surfaces"][0]["normal"];
      const auto entry = [&](int id, double shift, const std::string& body) {
        return "uavip-edits: 1\nsurfaces:\n  - id: " + std::to_string(id) +
               "\n    fingerprint: {centroid: [" + std::to_string(c[0].get<double>() + shift) +
               ", " + std::to_string(c[1].get<double>()) + ", " +
               std::to_string(c[2].get<double>()) + "], normal: [" + n[0].dump() + ", " +
               n[1].dump() + ", " + n[2].dump() + "]}\n" + body;
      };
      write("edits_id.yaml", entry(7, 0.0, "    delete: true\n"));
      write("edits_fingerprint.yaml", entry(0, 1.0, "    delete: true\n"));
      write("edits_bowtie.yaml",
            entry(0, 0.0, "    boundary: [[0, 0, 1], [2, 0, 3], [2, 0, 1], [0, 0, 3]]\n"));
      write("edits_off_plane.yaml",
            entry(0, 0.0, "    boundary: [[0, 0, 1], [2, 0, 1], [2, 2, 3]]\n"));
      write("edits_keep_out.yaml",
            "uavip-edits: 1\nkeep_out:\n  - name: all\n    box: {center: [4, -1.5, 2.5], size: "
            "[12, 2, 7]}\n");
      write("edits_key.yaml", "uavip-edits: 1\nkeep_outs: []\n");
    }
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static void write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
  }
  static std::string pcd(const std::string& fields, const std::string& size,
                         const std::string& type, const std::string& width,
                         const std::string& points, const std::string& data,
                         const std::string& body, const std::string& height = "1") {
    return "# .PCD v0.7\nVERSION 0.7\nFIELDS " + fields + "\nSIZE " + size + "\nTYPE " + type +
           "\nCOUNT 1 1 1\nWIDTH " + width + "\nHEIGHT " + height +
           "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + points + "\nDATA " + data + "\n" + body;
  }
  static std::string ply(const std::string& format, const std::string& vertices,
                         const std::string& props, const std::string& body, bool end = true) {
    return "ply\nformat " + format + " 1.0\nelement vertex " + vertices + "\n" + props +
           (end ? "end_header\n" : "") + body;
  }

  static void writeFixtures() {
    const std::string xyz3 = "property float x\nproperty float y\nproperty float z\n";
    write("empty.pcd", "");
    write("no_data.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nPOINTS 1\n");
    write("huge.pcd", pcd("x y z", "4 4 4", "F F F", "1000000000", "1000000000", "binary",
                          std::string(200, '\0')));
    write("neg_width.pcd", pcd("x y z", "4 4 4", "F F F", "-5", "5", "ascii", "1 2 3\n"));
    write("size3.pcd", pcd("x y z", "3 3 3", "F F F", "1", "1", "ascii", "1 2 3\n"));
    write("type_x.pcd", pcd("x y z", "4 4 4", "F X F", "1", "1", "ascii", "1 2 3\n"));
    write("half_float.pcd", pcd("x y z", "2 2 2", "F F F", "1", "1", "ascii", "1 2 3\n"));
    write("data_zip.pcd", pcd("x y z", "4 4 4", "F F F", "1", "1", "zip", "1 2 3\n"));
    write("wh_mismatch.pcd",
          pcd("x y z", "4 4 4", "F F F", "2", "5", "ascii", "1 2 3\n1 2 3\n", "2"));
    write("no_z.pcd", pcd("x y w", "4 4 4", "F F F", "1", "1", "ascii", "1 2 3\n"));
    write("nan.pcd", pcd("x y z", "4 4 4", "F F F", "2", "2", "ascii", "1 2 3\nnan 2 3\n"));
    write("points_text.pcd", pcd("x y z", "4 4 4", "F F F", "1", "1e3", "ascii", "1 2 3\n"));
    write("garbage.pcd", std::string("\x89\x01\x02\xff\xfe binary junk \x00\x01", 20));
    write("no_end.ply", ply("ascii", "1", xyz3, "1 2 3\n", false));
    write("neg_vertex.ply", ply("ascii", "-3", xyz3, "1 2 3\n"));
    write("huge.ply", ply("binary_little_endian", "1000000000", xyz3, std::string(64, '\0')));
    write("type.ply",
          ply("ascii", "1", "property quad x\nproperty float y\nproperty float z\n", "1 2 3\n"));
    write("format.ply", ply("utf8", "1", xyz3, "1 2 3\n"));
    write("no_xyz.ply",
          ply("ascii", "1", "property float a\nproperty float b\nproperty float c\n", "1 2 3\n"));
    write("not.ply", "solid cube\nfacet normal 0 0 1\n");
    write("empty.xyz", "");
    write("letters.xyz", "1 2 3\na b c\n");
    write("nan.xyz", "1 2 3\nnan 2 3\n");
    write("two_cols.xyz", "1 2\n3 4\n");
    write("cloud.foo", "1 2 3\n");
    write("short.las", "LASF" + std::string(40, '\0'));
    write("c.laz", "LASF");
    fs::create_directories(dir_ / "a_dir.pcd");
    ::mkfifo((dir_ / "fifo.pcd").c_str(), 0600);
    // Configs.
    write("dup.yaml", "preprocess: {voxel_m: 0.05}\npreprocess: {voxel_m: 0.1}\n");
    write("unknown.yaml", "preprocess: {voxel: 0.05}\n");
    write("type.yaml", "preprocess: {voxel_m: abc}\n");
    write("negative.yaml", "preprocess: {voxel_m: -1}\n");
    write("scale.yaml", "input: {scale: -0.001}\n");
    write("complex.yaml", "? [a, b]\n: 1\n");
    write("reserve.yaml", "flight: {reserve: 1}\n");
    write("home2.yaml", "mission: {home: [1, 2]}\n");
    write("syntax.yaml", "preprocess: {voxel_m: [1, 2\n");
    write("planner.yaml", "planner: {name: warp}\n");
    // Structure coverage: impossible cameras, conflicting keys, a standoff inside the clearance.
    write("fx0.yaml", "camera: {fx: 0, fy: 400, image_px: [640, 480]}\n");
    write("image_neg.yaml", "camera: {fx: 400, fy: 400, image_px: [-640, 480]}\n");
    write("fx_focal.yaml", "camera: {fx: 400, fy: 400, image_px: [640, 480], focal_mm: 8.8}\n");
    write("standoff_in.yaml", "coverage: {standoff_m: 0.5}\nuav: {inflation_radius_m: 0.6}\n");
    write("mode.yaml", "coverage: {mode: everything}\n");
    write("min_views.yaml", "coverage: {purpose: reconstruction, min_views: 1}\n");
    write("start_in.yaml", "mission: {start: [0, 0, 1.5]}\n");  // inside the single_plane wall
    write("home_in.yaml", "mission: {home: [0, 0, 1.5]}\n");
    write("start_far.yaml", "mission: {start: [100000, 0, 2]}\n");  // 100 km: beyond one battery
    write("home_far.yaml", "mission: {home: [0, 1e7, 2]}\n");       // 10,000 km
    write("speed0.yaml", "flight: {cruise_speed_m_s: 0}\n");
    write("camera.yaml", "camera: {footprint_m: [0, 1]}\n");
    write("overlap.yaml", "coverage: {overlap_w: 1.5}\n");
    write("tiny.yaml", "camera: {footprint_m: [0.001, 0.001]}\n");
    // Scenarios.
    write("no_world.yaml", "name: x\n");
    const std::string wall =
        "name: x\nworld:\n  - {type: plane, name: w, corner: [0, 0, 0], edge_u: [4, 0, 0], edge_v: "
        "[0, 0, 2]}\n";
    write("turn3600.yaml", wall +
                               "sensing: {mode: scan, stations: [[1, -3, 1], [2, -3, 1], [3, -3, "
                               "1]], turn_deg: 3600}\n");
    std::string stations;
    for (int i = 0; i < 200; ++i)
      stations += std::string(i ? ", " : "") + "[" + std::to_string(i) + ", -3, 1]";
    write("stations200.yaml", wall + "sensing: {mode: scan, stations: [" + stations + "]}\n");
    write(
        "bad_mode.yaml",
        "name: x\nworld:\n  - {type: point, name: p, at: [0, 0, 2]}\nsensing: {mode: teleport}\n");
    write("fine.yaml",
          "name: x\nworld:\n  - {type: plane, name: w, corner: [0, 0, 0], edge_u: [40, 0, 0], "
          "edge_v: [0, 0, 20]}\n"
          "sensing: {mode: sample, spacing_m: 0.0001}\n");
    write("bad_prim.yaml", "name: x\nworld:\n  - {type: sphere, name: s, at: [0, 0, 2]}\n");
    write("world_map.yaml", "name: x\nworld: {spheres: [{c: [0,0,0]}]}\n");
    // Scene and mission JSON.
    write("not.json", "{ not json");
    write("scene_nosurf.json", "{\"cloud\": []}");
    write("mission_nosurf.json", "{\"inflation_radius_m\": 0.6}");
    write("mission_badwp.json",
          "{\"inflation_radius_m\": 0.6, \"surfaces\": [{\"surface_id\": 0, \"status\": \"ok\", "
          "\"stops\": [], "
          "\"waypoints\": [[1, \"a\", 3]]}]}");
    // A surface path 60 km from the origin (within the file's 1,000 km), and one at 1e155 m.
    const std::string far_surface =
        "{\"inflation_radius_m\": 0.6, \"surfaces\": [{\"surface_id\": 0, \"status\": \"ok\", "
        "\"stops\": "
        "[{\"position\": [60000, 0, 5], \"yaw_deg\": 0, \"gimbal_pitch_deg\": 0}], \"waypoints\": "
        "[[60000, 0, 5], [WP]]}]}";
    write("mission_far.json", std::regex_replace(far_surface, std::regex("WP"), "60001, 0, 5"));
    write("mission_1e155.json", std::regex_replace(far_surface, std::regex("WP"), "1e155, 0, 5"));
    // Hostile numbers: a stray point at 1e308, a wall scaled by 1e12, a
    // 0.1 mm planning grid, a GSD in the wrong unit, a name with a newline.
    std::string wall_xyz, wall_1e12;
    for (int i = 0; i <= 40; ++i) {
      for (int j = 0; j <= 20; ++j) {
        wall_xyz += std::to_string(i * 0.1) + " 0 " + std::to_string(j * 0.1) + "\n";
        wall_1e12 += std::to_string(i * 1e11) + " 0 " + std::to_string(j * 1e11) + "\n";
      }
    }
    write("wall.xyz", wall_xyz);
    write("far_point.xyz", wall_xyz + "1e308 0 0\n");
    write("far_point_neg.pcd",
          pcd("x y z", "8 8 8", "F F F", "3", "3", "ascii", "1 2 3\n-1e308 0 0\n1 2 4\n"));
    write("wall_1e12.xyz", wall_1e12);
    write("scale_1e12.yaml", "input: {scale: 1e12}\n");
    write("res_1e-4.yaml", "grid: {resolution_m: 1e-4}\n");
    write("gsd_1e6.yaml",
          "camera: {sensor_mm: [13.2, 8.8], focal_mm: 8.8, image_px: [5472, 3648], gsd_mm_per_px: "
          "1e6}\n");
    write("range.yaml",
          "camera: {footprint_m: [0.6, 0.4], max_range_m: 10}\ncoverage: {standoff_m: 20}\n");
    write("standoff_2km.yaml", "coverage: {standoff_m: 2000}\n");
    write("two\nlines.xyz", "1 2\n");
    // Scans folder with a file an output could overwrite.
    write("scans/cloud.pcd", "keep");
  }

  static fs::path dir_;
  static Result good_;
  static std::vector<std::string> before_;
};

fs::path BadInput::dir_;
Result BadInput::good_;
std::vector<std::string> BadInput::before_;

std::string replaceAll(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
  return s;
}

TEST_F(BadInput, EveryCaseIsOneLineWithItsExitCodeAndNothingIsLost) {
  ASSERT_EQ(good_.code, 0) << good_.out;
  const std::string S = std::string(UAVIP_SOURCE_DIR) + "/scenarios/";
  const std::string scene = "$D/prev/scene.json", mission = "$D/prev/mission.json";
  const std::string exp = "export " + mission + " --format wpl --origin 47.4,8.5,488 ";
  const std::vector<Case> cases = {
      // Clouds (detect writes into prev/: nothing there may change).
      {"empty pcd", "detect $D/empty.pcd -o $D/prev", 2, "empty.pcd"},
      {"pcd without DATA", "detect $D/no_data.pcd -o $D/prev", 2, "DATA"},
      {"pcd claiming 1e9 points in 200 bytes", "detect $D/huge.pcd -o $D/prev", 2,
       "claims 1000000000 points"},
      {"pcd negative WIDTH", "detect $D/neg_width.pcd -o $D/prev", 2, "WIDTH"},
      {"pcd SIZE 3", "detect $D/size3.pcd -o $D/prev", 2, "SIZE"},
      {"pcd TYPE X", "detect $D/type_x.pcd -o $D/prev", 2, "TYPE"},
      {"pcd 2-byte float", "detect $D/half_float.pcd -o $D/prev", 2, "float of 2 bytes"},
      {"pcd DATA zip", "detect $D/data_zip.pcd -o $D/prev", 2, "DATA"},
      {"pcd WIDTH x HEIGHT != POINTS", "detect $D/wh_mismatch.pcd -o $D/prev", 2,
       "differs from POINTS"},
      {"pcd without z", "detect $D/no_z.pcd -o $D/prev", 2, "x y z"},
      {"pcd with a NaN point", "detect $D/nan.pcd -o $D/prev", 2, "not finite"},
      {"pcd POINTS 1e3", "detect $D/points_text.pcd -o $D/prev", 2, "POINTS"},
      {"binary junk as pcd", "detect $D/garbage.pcd -o $D/prev", 2, "garbage.pcd"},
      {"ply without end_header", "detect $D/no_end.ply -o $D/prev", 2, "end_header"},
      {"ply negative vertex count", "detect $D/neg_vertex.ply -o $D/prev", 2, "element vertex"},
      {"ply claiming 1e9 vertices", "detect $D/huge.ply -o $D/prev", 2, "claims 1000000000 points"},
      {"ply unknown property type", "detect $D/type.ply -o $D/prev", 2, "quad"},
      {"ply unknown format", "detect $D/format.ply -o $D/prev", 2, "format"},
      {"ply without x y z", "detect $D/no_xyz.ply -o $D/prev", 2, "x y z"},
      {"not a ply", "detect $D/not.ply -o $D/prev", 2, "not a PLY"},
      {"empty xyz", "detect $D/empty.xyz -o $D/prev", 2, "empty.xyz"},
      {"xyz with letters", "detect $D/letters.xyz -o $D/prev", 2, "letters.xyz"},
      {"xyz with NaN", "detect $D/nan.xyz -o $D/prev", 2, "nan.xyz"},
      {"xyz with two columns", "detect $D/two_cols.xyz -o $D/prev", 2, "two_cols.xyz"},
      {"unknown extension", "detect $D/cloud.foo -o $D/prev", 2, "unknown cloud extension"},
      {"missing cloud", "detect $D/nope.pcd -o $D/prev", 2, "no such file"},
      {"folder as cloud", "detect $D/a_dir.pcd -o $D/prev", 2, "is a directory"},
      {"/dev/zero as cloud", "detect /dev/zero -o $D/prev", 2, "not a regular file"},
      {"FIFO as cloud", "detect $D/fifo.pcd -o $D/prev", 2, "not a regular file"},
      {"truncated las", "detect $D/short.las -o $D/prev", 2, "short.las"},
      {"laz", "detect $D/c.laz -o $D/prev", 2, "laz"},
      {"output onto a file", "detect " + S + "../tests/data/room_scan1.pcd -o $D/empty.xyz", 2,
       "not a directory"},
      // Configs.
      {"duplicate YAML key", "detect $D/nan.xyz -c $D/dup.yaml -o $D/prev", 2, "dup.yaml"},
      {"unknown config key", "plan " + scene + " --surface 0 -c $D/unknown.yaml -o $D/prev", 2,
       "voxel"},
      {"config value of the wrong type",
       "plan " + scene + " --surface 0 -c $D/type.yaml -o $D/prev", 2, "voxel_m"},
      {"negative voxel", "plan " + scene + " --surface 0 -c $D/negative.yaml -o $D/prev", 2,
       "voxel_m"},
      {"negative input.scale", "detect $D/letters.xyz -c $D/scale.yaml -o $D/prev", 2,
       "scale must be > 0"},
      {"complex YAML key", "plan " + scene + " --surface 0 -c $D/complex.yaml -o $D/prev", 2,
       "complex.yaml"},
      {"reserve 1", "plan " + scene + " --surface 0 -c $D/reserve.yaml -o $D/prev", 2, "reserve"},
      {"home with two numbers", "plan " + scene + " --surface 0 -c $D/home2.yaml -o $D/prev", 2,
       "home"},
      {"YAML syntax error", "plan " + scene + " --surface 0 -c $D/syntax.yaml -o $D/prev", 2,
       "syntax.yaml"},
      {"unknown planner in config", "plan " + scene + " --surface 0 -c $D/planner.yaml -o $D/prev",
       2, "warp"},
      {"--cover with --surface", "plan " + scene + " --cover structure --surface 0 -o $D/prev", 2,
       "--surface"},
      {"--cover unknown", "plan " + scene + " --cover roof -o $D/prev", 2, "roof"},
      {"plan with neither --surface nor --cover", "plan " + scene + " -o $D/prev", 2,
       "--cover structure"},
      {"pinhole with zero focal length",
       "plan " + scene + " --cover structure -c $D/fx0.yaml -o $D/prev", 2, "fx"},
      {"pinhole with a negative image",
       "plan " + scene + " --cover structure -c $D/image_neg.yaml -o $D/prev", 2, "image_px"},
      {"pinhole and sensor keys",
       "plan " + scene + " --cover structure -c $D/fx_focal.yaml -o $D/prev", 2, "focal_mm"},
      {"viewing distance inside the clearance",
       "plan " + scene + " --cover structure -c $D/standoff_in.yaml -o $D/prev", 2, "standoff_m"},
      {"unknown coverage mode", "plan " + scene + " --cover structure -c $D/mode.yaml -o $D/prev",
       2, "everything"},
      {"a reconstruction with one view a point",
       "plan " + scene + " --cover structure -c $D/min_views.yaml -o $D/prev", 2, "min_views"},
      {"start inside the wall", "plan " + scene + " --surface 0 -c $D/start_in.yaml -o $D/prev", 2,
       "start"},
      {"home inside the wall", "plan " + scene + " --surface 0 -c $D/home_in.yaml -o $D/prev", 2,
       "home"},
      {"start 100 km away", "plan " + scene + " --surface 0 -c $D/start_far.yaml -o $D/prev", 2,
       "battery's reach"},
      {"home 10,000 km away", "plan " + scene + " --surface 0 -c $D/home_far.yaml -o $D/prev", 2,
       "mission.home"},
      {"cruise speed 0", "plan " + scene + " --surface 0 -c $D/speed0.yaml -o $D/prev", 2,
       "cruise_speed_m_s"},
      {"zero footprint", "plan " + scene + " --surface 0 -c $D/camera.yaml -o $D/prev", 2,
       "footprint"},
      {"1 mm footprint: 32 million stops",
       "plan " + scene + " --surface 0 -c $D/tiny.yaml -o $D/prev", 2, "max_stops"},
      {"overlap 1.5", "plan " + scene + " --surface 0 -c $D/overlap.yaml -o $D/prev", 2, "overlap"},
      {"config is a folder", "plan " + scene + " --surface 0 -c $D/a_dir.pcd -o $D/prev", 2,
       "is a directory"},
      {"missing config", "plan " + scene + " --surface 0 -c $D/nope.yaml -o $D/prev", 2,
       "nope.yaml"},
      // Scenarios (run writes into prev/).
      {"missing scenario", "run $D/nope.yaml -o $D/prev", 2, "nope.yaml"},
      {"scenario without world", "run $D/no_world.yaml -o $D/prev", 2, "world"},
      {"three 3600 deg turns: 31 M range readings", "run $D/turn3600.yaml -o $D/prev", 2,
       "max_readings"},
      {"200 scan stations", "run $D/stations200.yaml -o $D/prev", 2, "200 stations"},
      {"unknown sensing mode", "run $D/bad_mode.yaml -o $D/prev", 2, "teleport"},
      {"unknown primitive", "run $D/bad_prim.yaml -o $D/prev", 2, "sphere"},
      {"0.1 mm sampling of a 40 x 20 m wall", "run $D/fine.yaml -o $D/prev", 2, "spacing_m"},
      {"world not a list", "run $D/world_map.yaml -o $D/prev", 2, "world"},
      {"scenario YAML syntax", "run $D/syntax.yaml -o $D/prev", 2, "syntax.yaml"},
      {"unknown planner flag", "run " + S + "single_plane.yaml --planner warp -o $D/prev", 2,
       "warp"},
      {"surface that does not exist", "run " + S + "single_plane.yaml --surface 7 -o $D/prev", 2,
       "no surface with id 7"},
      // Scene selection.
      {"scene not JSON", "plan $D/not.json --surface 0 -o $D/prev", 2, "not.json"},
      {"scene id beyond int", "plan $D/scene_bigid.json --surface all -o $D/prev", 2,
       "surfaces[0].id"},
      {"scene id used twice", "plan $D/scene_twice.json --surface all -o $D/prev", 2,
       "ids must differ"},
      {"scene negative area", "plan $D/scene_negative.json --surface all -o $D/prev", 2, "area_m2"},
      {"scene without surfaces", "plan $D/scene_nosurf.json --surface 0 -o $D/prev", 2,
       "scene_nosurf.json"},
      {"missing scene", "plan $D/nope.json --surface 0 -o $D/prev", 2, "nope.json"},
      {"surface id 99", "plan " + scene + " --surface 99 -o $D/prev", 2, "no surface with id 99"},
      {"surface id text", "plan " + scene + " --surface abc -o $D/prev", 2, "'abc'"},
      {"surface listed twice", "plan " + scene + " --surface 0,0 -o $D/prev", 2, "listed twice"},
      {"empty surface list", "plan " + scene + " --surface , -o $D/prev", 2, "--surface"},
      {"surface id beyond int", "plan " + scene + " --surface 4294967296 -o $D/prev", 2,
       "4294967296"},
      // Export.
      {"export without origin", "export " + mission + " --format wpl -o $D/x.wpl", 2, "--origin"},
      {"export origin of two numbers",
       "export " + mission + " --format wpl --origin 47.4,8.5 -o $D/x.wpl", 2, "47.4,8.5"},
      {"export origin twice", exp + "--origin 47.4,8.5,1 -o $D/x.wpl", 2, "--origin"},
      {"export latitude 95", "export " + mission + " --format wpl --origin 95,8.5,488 -o $D/x.wpl",
       2, "latitude"},
      {"export unknown format", "export " + mission + " --format kmz --origin 1,2,3 -o $D/x", 2,
       "kmz"},
      {"export dji unknown drone",
       "export " + mission + " --surface all --format dji-kmz --origin 1,2,3 --drone mini4 -o $D/x",
       2, "mini4"},
      {"export dji unknown vertical datum",
       "export " + mission +
           " --surface all --format kml --crs EPSG:32631 --vertical navd88 -o $D/x",
       2, "navd88"},
      {"export unknown autopilot", exp + "--autopilot betaflight -o $D/x.wpl", 2, "betaflight"},
      {"export negative hold", exp + "--hold -1 -o $D/x.wpl", 2, "--hold"},
      {"export zero speed", exp + "--speed 0 -o $D/x.wpl", 2, "--speed"},
      {"export missing mission", "export $D/nope.json --format wpl --origin 1,2,3 -o $D/x.wpl", 2,
       "nope.json"},
      {"export mission not JSON", "export $D/not.json --format wpl --origin 1,2,3 -o $D/x.wpl", 2,
       "not.json"},
      {"export surface 9", exp + "--surface 9 -o $D/x.wpl", 2, "no surface with id 9"},
      {"export sortie 5", exp + "--surface all --sortie 5 -o $D/x.wpl", 2, "--sortie"},
      {"export onto its mission", exp + "--surface all -o " + mission, 2, "would overwrite"},
      {"export onto a folder", exp + "--surface all -o $D/a_dir.pcd", 2, "is a directory"},
      {"export with a missing scene", exp + "--surface all --scene $D/nope.json -o $D/x.wpl", 2,
       "nope.json"},
      {"export a mission without surfaces",
       "export $D/mission_nosurf.json --format wpl --origin 1,2,3 -o $D/x.wpl", 2, "surfaces"},
      // Validate.
      {"validate missing mission", "validate $D/nope.json", 2, "nope.json"},
      {"validate a waypoint of text", "validate $D/mission_badwp.json --scene " + scene, 2,
       "waypoints[0]"},
      {"validate a waypoint at 1e155 m", "validate $D/mission_1e155.json --scene " + scene, 2,
       "waypoints[1]"},
      {"export a flight 60 km from the origin",
       "export $D/mission_far.json --format wpl --origin 47,8,400 -o $D/x.wpl", 2,
       "60.0 km from the origin"},
      {"validate negative clearance", "validate " + mission + " --clearance -1", 2, "--clearance"},
      {"validate a mission without surfaces", "validate $D/mission_nosurf.json --scene " + scene, 2,
       "surfaces"},
      // Hostile numbers.
      {"a point at 1e308", "detect $D/far_point.xyz -o $D/prev", 2, "point 861 (1e+308, 0, 0)"},
      {"a point at -1e308 in a double PCD", "detect $D/far_point_neg.pcd -o $D/prev", 2,
       "point 1 (-1e+308, 0, 0)"},
      {"a wall scaled by 1e12", "detect $D/wall_1e12.xyz -o $D/prev", 2, "spans 4e+12 m"},
      {"input.scale 1e12", "detect $D/wall.xyz -c $D/scale_1e12.yaml -o $D/prev", 2,
       "spans 4e+12 m"},
      {"grid.resolution_m 1e-4", "plan " + scene + " --surface 0 -c $D/res_1e-4.yaml -o $D/prev", 2,
       "grid.resolution_m >="},
      {"GSD 1e6 mm/px: a 3,648 km standoff",
       "plan " + scene + " --surface 0 -c $D/gsd_1e6.yaml -o $D/prev", 2,
       "3.648e+06 m from the surface"},
      {"standoff beyond max_range_m", "plan " + scene + " --surface 0 -c $D/range.yaml -o $D/prev",
       2, "max_range_m 10"},
      {"standoff 2 km without max_range_m",
       "plan " + scene + " --surface 0 -c $D/standoff_2km.yaml -o $D/prev", 2, "standoff_m 2000"},
      {"a newline in a file name", "detect '$D/two\nlines.xyz' -o $D/prev", 2, "two\\nlines.xyz"},
      // Edits files: plan writes into prev/, nothing there may change.
      {"edits unknown surface",
       "plan " + scene + " --surface all --edits $D/edits_id.yaml -o $D/prev", 2,
       "edits_id.yaml:3: surfaces[0]: no surface with id 7"},
      {"edits of another detection",
       "plan " + scene + " --surface all --edits $D/edits_fingerprint.yaml -o $D/prev", 2,
       "does not match the fingerprint"},
      {"edits self-intersecting boundary",
       "plan " + scene + " --surface all --edits $D/edits_bowtie.yaml -o $D/prev", 2,
       "intersects itself"},
      {"edits vertex off the plane",
       "plan " + scene + " --surface all --edits $D/edits_off_plane.yaml -o $D/prev", 2,
       "off the plane of surface 0"},
      {"edits keep-out over every stop",
       "plan " + scene + " --surface all --edits $D/edits_keep_out.yaml -o $D/prev", 2,
       "keep_out[0] 'all' contains every photo stop of surface 0"},
      {"edits unknown key", "plan " + scene + " --surface all --edits $D/edits_key.yaml -o $D/prev",
       2, "keep_outs"},
      // Command line.
      {"unknown command", "fly", 2, "fly"},
      {"unknown option", "run --warp 9", 2, "--warp"},
      {"detect without -o", "detect $D/nan.xyz", 2, "--out"},
      {"quiet and verbose", "-v run " + S + "single_plane.yaml -o $D/prev", 2,
       "--quiet and --verbose"},
      {"runs not a number", "bench " + S + "bench_cube_around.yaml --runs many -o $D/b.log", 2,
       "many"},
      // Outputs that would overwrite an input or each other.
      {"bench of 55,000 h worst case",
       "bench " + S + "bench_cube_around.yaml --runs 10000 --time-limit 600 -o $D/b.log", 2,
       "--max-total"},
      {"bench log onto its own csv", "bench " + S + "bench_cube_around.yaml --runs 1 -o $D/r.csv",
       2, "same file"},
      {"bench missing scenario", "bench $D/nope.yaml -o $D/b.log", 2, "nope.yaml"},
      {"assemble into .xyz", "assemble $D/scans -o $D/x.xyz", 2, ".pcd"},
      {"assemble onto an input", "assemble $D/scans -o $D/scans/cloud.pcd", 2, "would overwrite"},
      {"assemble a folder without a log", "assemble $D/a_dir.pcd -o $D/x.pcd", 2, "a_dir.pcd"},
  };
  ASSERT_GE(cases.size(), 80u);
  for (const Case& c : cases) {
    const std::string args = replaceAll(c.args, "$D", dir_.string());
    const Result r = uavip("-q " + args);
    EXPECT_EQ(r.code, c.code) << c.name << ": uavip -q " << args << "\n" << r.out;
    const auto lines = std::count(r.out.begin(), r.out.end(), '\n');
    EXPECT_EQ(lines, 1) << c.name << ": one line expected\n" << r.out;
    EXPECT_EQ(r.out.rfind(c.code == 2 ? "uavip: error: " : "uavip: ", 0), 0u) << c.name << "\n"
                                                                              << r.out;
    EXPECT_NE(r.out.find(c.fragment), std::string::npos)
        << c.name << ": '" << c.fragment << "' expected\n"
        << r.out;
    EXPECT_LT(r.out.size(), 600u) << c.name << ": no echo of binary content\n"
                                  << r.out.substr(0, 600);
  }
  // The earlier results in prev/ are untouched.
  const char* files[] = {"scene.json", "mission.json", "cloud_clean.pcd", "overview.png",
                         "path.obj"};
  for (std::size_t i = 0; i < before_.size(); ++i)
    EXPECT_EQ(slurp(dir_ / "prev" / files[i]), before_[i]) << files[i] << " changed";
  EXPECT_FALSE(fs::exists(dir_ / "x.wpl"));
  EXPECT_EQ(slurp(dir_ / "scans/cloud.pcd"), "keep");
#if !defined(__SANITIZE_ADDRESS__)
  // Memory: no case used more than 1 GB (the largest child's peak resident set).
  rusage usage{};
  ::getrusage(RUSAGE_CHILDREN, &usage);
  EXPECT_LT(usage.ru_maxrss, 1024L * 1024L) << "peak " << usage.ru_maxrss << " KiB";
#endif
}

}  // namespace
