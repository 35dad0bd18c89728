// `uavip assemble` as a user runs it: a small simulated raw log (a room, two
// stations) becomes a merged cloud and cloud.report.json that agree with the
// simulator's truth.json; bad raw data exits 2 with one line naming the file (and
// line) and leaves an earlier cloud untouched; `-c` applies a config's
// `registration:` section.

#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.h"

namespace {

namespace fs = std::filesystem;

using uavip::cli_test::Result;
using uavip::cli_test::slurp;
using uavip::cli_test::uavip;
using Vec3 = Eigen::Vector3d;

// A 9 × 7 × 4 m room with a pillar and a yawed crate (as tests/scan), two stations,
// a fast turn (180 deg/s: 81 scans per scanner per station) with the simulator's
// default noise, wind and GPS error, so the run stays small.
const char* kScenario = R"(name: assemble_cli_room
world:
  - {type: box, name: room, min: [-4, -3, -1.5], max: [5, 4, 2.5]}
  - {type: box, name: pillar, min: [2, 1.5, -1.5], max: [2.6, 2.1, 2.5]}
  - {type: box, name: crate, min: [-3, -2.5, -1.5], max: [-2, -1.7, -0.7], yaw_deg: 20}
sensing:
  mode: scan
  stations: [[0.3, 0.2, 0], [2.5, -1.0, 0.3]]
  yaw_rate_deg_s: 180
  seed: 5
)";

nlohmann::json readJson(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

Vec3 vec(const nlohmann::json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

std::size_t lines(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

/// The points of a PCD file (x y z float, ascii or binary), read by hand.
std::vector<Vec3> readPcd(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::vector<Vec3> out;
  std::string line, data;
  std::size_t n = 0, fields = 0;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "POINTS") ls >> n;
    if (key == "FIELDS") {
      for (std::string f; ls >> f;) ++fields;
    }
    if (key == "DATA") {
      ls >> data;
      break;
    }
  }
  if (fields != 3) return out;
  if (data == "binary") {
    std::vector<float> buf(3 * n);
    in.read(reinterpret_cast<char*>(buf.data()),
            static_cast<std::streamsize>(buf.size() * sizeof(float)));
    if (!in) return out;
    for (std::size_t i = 0; i < n; ++i)
      out.emplace_back(buf[3 * i], buf[3 * i + 1], buf[3 * i + 2]);
  } else if (data == "ascii") {
    double x = 0, y = 0, z = 0;
    while (out.size() < n && in >> x >> y >> z) out.emplace_back(x, y, z);
  }
  return out;
}

/// Distance from p to the rectangle corner + s·u + t·v, s, t ∈ [0, 1] (u ⟂ v).
double rectDistance(const Vec3& p, const Vec3& corner, const Vec3& u, const Vec3& v) {
  const Vec3 d = p - corner;
  const double s = std::clamp(d.dot(u) / u.squaredNorm(), 0.0, 1.0);
  const double t = std::clamp(d.dot(v) / v.squaredNorm(), 0.0, 1.0);
  return (d - s * u - t * v).norm();
}

class AssembleCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("uavip_assemble_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "room.yaml") << kScenario;
    simulate_ = uavip("simulate " + (dir_ / "room.yaml").string() + " -q -o " + scans().string());
    if (simulate_.code == 0)
      assemble_ = uavip("assemble " + scans().string() + " -q -o " + cloud().string());
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static fs::path scans() { return dir_ / "scans"; }
  static fs::path cloud() { return dir_ / "out" / "cloud.pcd"; }
  static fs::path reportOf(const fs::path& pcd) {
    return fs::path(pcd).replace_extension(".report.json");
  }

  /// A copy of the simulated raw log, to damage.
  static fs::path copyOfScans(const std::string& name) {
    const fs::path d = dir_ / name;
    fs::remove_all(d);
    fs::copy(scans(), d);
    return d;
  }

  /// `uavip assemble` on a bad log: exit 2, one line matching `pattern`, and the
  /// cloud and report already at the output path are left as they were.
  static void expectBad(const std::string& args, const std::string& pattern) {
    const fs::path out = dir_ / "kept" / "cloud.pcd";
    fs::create_directories(out.parent_path());
    std::ofstream(out) << "earlier cloud";
    std::ofstream(reportOf(out)) << "earlier report";
    const Result r = uavip("assemble " + args + " -o " + out.string());
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
    EXPECT_TRUE(std::regex_search(r.out, std::regex(pattern)))
        << "'" << pattern << "' not in: " << r.out;
    EXPECT_EQ(lines(r.out), 1u) << r.out;
    EXPECT_EQ(slurp(out), "earlier cloud");
    EXPECT_EQ(slurp(reportOf(out)), "earlier report");
  }

  static inline fs::path dir_;
  static inline Result simulate_, assemble_;
};

TEST_F(AssembleCli, CloudAndReportMatchTheTruth) {
  ASSERT_EQ(simulate_.code, 0) << simulate_.out;
  ASSERT_EQ(assemble_.code, 0) << assemble_.out;
  const nlohmann::json log = readJson(scans() / "log.json");
  const nlohmann::json truth = readJson(scans() / "truth.json");
  const nlohmann::json report = readJson(reportOf(cloud()));

  // The cloud: as many points as the report says, all finite.
  const std::vector<Vec3> points = readPcd(cloud());
  ASSERT_GT(points.size(), 0u);
  EXPECT_EQ(report["cloud"]["points"].get<std::size_t>(), points.size());

  // One entry per station of the log, in order, placed within 3 cm of the truth.
  ASSERT_EQ(log["stations"].size(), 2u);
  ASSERT_EQ(report["stations"].size(), log["stations"].size());
  const Vec3 recorded0 = vec(log["stations"][0]["recorded_position_m"]);
  for (std::size_t i = 0; i < report["stations"].size(); ++i) {
    SCOPED_TRACE("station " + std::to_string(i));
    const auto& s = report["stations"][i];
    EXPECT_EQ(s["id"], log["stations"][i]["id"]);
    EXPECT_GT(s["points"].get<std::size_t>(), 0u);
    EXPECT_TRUE(s["registered"].get<bool>());
    // The initial position is the recorded one (relative to station 0).
    const Vec3 recorded = vec(log["stations"][i]["recorded_position_m"]) - recorded0;
    EXPECT_LT((vec(s["initial_position"]) - recorded).norm(), 1e-9);
    // The station frame's origin: the UAV centre at its first horizontal scan.
    const auto& poses = truth["stations"][i]["horizontal_poses"];
    ASSERT_GT(poses.size(), 1u);
    const Vec3 origin(poses[0][0].get<double>(), poses[0][1].get<double>(),
                      poses[0][2].get<double>());
    EXPECT_LT((vec(s["position"]) - origin).norm(), 0.03);
    EXPECT_NEAR(s["truth"]["position_error_m"].get<double>(), (vec(s["position"]) - origin).norm(),
                1e-9);
    // The room has walls facing every direction: every position is fixed by the scans
    // (station 0 is the reference and has no pairs of its own).
    EXPECT_TRUE(s["position_observed"].get<bool>());
    if (i > 0) {
      EXPECT_GE(s["registration_information_pairs"][0].get<double>(), 20.0);
    }
    // Loop closure: the loop of every station closes within 5 cm at the default noise.
    EXPECT_GE(s["loop_closure_m"].get<double>(), 0.0);
    EXPECT_LE(s["loop_closure_m"].get<double>(), 0.05);
    // Drift: the largest true displacement during the turn, from truth.json, and the
    // estimate within 3 cm of it.
    double true_max = 0.0;
    for (const auto& p : poses) {
      true_max = std::max(
          true_max,
          (Vec3(p[0].get<double>(), p[1].get<double>(), p[2].get<double>()) - origin).norm());
    }
    EXPECT_GT(true_max, 0.02);  // the wind did move the UAV
    EXPECT_NEAR(s["truth"]["true_drift_max_m"].get<double>(), true_max, 1e-9);
    EXPECT_NEAR(s["drift_max_m"].get<double>(), true_max, 0.03);
    EXPECT_LE(s["drift_final_m"].get<double>(), s["drift_max_m"].get<double>());
    EXPECT_LE(s["truth"]["drift_error_max_m"].get<double>(), 0.05);
  }
  // The GPS error is real: registration had something to correct.
  EXPECT_GT(report["stations"][1]["truth"]["initial_position_error_m"].get<double>(), 0.1);

  // RMS of the merged cloud to the true surfaces: the report's number, and the same
  // computed here from truth.json's rectangles on an even subsample.
  ASSERT_TRUE(report.contains("truth"));
  const double reported = report["truth"]["rms_to_truth_m"].get<double>();
  EXPECT_LE(reported, 0.03);
  ASSERT_EQ(truth["world"]["rects"].size(), 18u);  // three boxes
  std::vector<std::array<Vec3, 3>> rects;
  for (const auto& r : truth["world"]["rects"])
    rects.push_back({vec(r["corner"]), vec(r["edge_u"]), vec(r["edge_v"])});
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < points.size(); i += 25, ++n) {
    double d = 1e9;
    for (const auto& r : rects) d = std::min(d, rectDistance(points[i], r[0], r[1], r[2]));
    sum += d * d;
  }
  const double rms = std::sqrt(sum / static_cast<double>(n));
  EXPECT_LE(rms, 0.03);
  EXPECT_NEAR(rms, reported, 0.003);  // float PCD, subsample
}

TEST_F(AssembleCli, ConfigWithoutRegistrationKeepsTheRecordedPoses) {
  ASSERT_EQ(simulate_.code, 0) << simulate_.out;
  const fs::path config = dir_ / "none.yaml";
  std::ofstream(config) << "registration: {method: none, output_voxel_m: 0.05}\n";
  const fs::path out = dir_ / "none" / "cloud.pcd";
  const Result r =
      uavip("assemble " + scans().string() + " -q -c " + config.string() + " -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json log = readJson(scans() / "log.json");
  const nlohmann::json report = readJson(reportOf(out));
  EXPECT_EQ(report["options"]["registration"], "none");
  EXPECT_DOUBLE_EQ(report["options"]["output_voxel_m"].get<double>(), 0.05);
  ASSERT_EQ(report["stations"].size(), log["stations"].size());
  const Vec3 recorded0 = vec(log["stations"][0]["recorded_position_m"]);
  for (std::size_t i = 0; i < report["stations"].size(); ++i) {
    SCOPED_TRACE("station " + std::to_string(i));
    const Vec3 recorded = vec(log["stations"][i]["recorded_position_m"]) - recorded0;
    EXPECT_LT((vec(report["stations"][i]["position"]) - recorded).norm(), 1e-9);
    EXPECT_NEAR(report["stations"][i]["rotation_deg"].get<double>(), 0.0, 1e-9);
  }
  // Station 1's recorded position carries the GPS error, so the merged cloud is worse
  // than with registration (the default run above: <= 3 cm).
  EXPECT_GT(report["stations"][1]["truth"]["position_error_m"].get<double>(), 0.1);
  EXPECT_GT(readPcd(out).size(), 0u);
}

TEST_F(AssembleCli, BadInputExits2WithOneLineNamingTheFile) {
  ASSERT_EQ(simulate_.code, 0) << simulate_.out;
  // A missing directory.
  const fs::path missing = dir_ / "no_such_scans";
  expectBad(missing.string(),
            std::regex_replace(missing.string(), std::regex("[.]"), "[.]") + ".*log[.]json");

  // A scan line cut in the middle: keep the header and 9 scans, then half of line 11.
  {
    const fs::path d = copyOfScans("cut");
    const fs::path f = d / "station_1_vertical.csv";
    std::istringstream in(slurp(f));
    std::string text, l;
    for (int i = 0; i < 10 && std::getline(in, l); ++i) text += l + "\n";
    ASSERT_TRUE(std::getline(in, l));
    text += l.substr(0, l.size() / 2);
    std::ofstream(f, std::ios::trunc) << text;
    expectBad(d.string(), "station_1_vertical[.]csv:11: .*truncated");
  }
  // A station with no horizontal scans (the header line only).
  {
    const fs::path d = copyOfScans("empty");
    const fs::path f = d / "station_1_horizontal.csv";
    std::string header;
    std::getline(std::ifstream(f), header);
    ASSERT_EQ(header.rfind('#', 0), 0u) << header;
    std::ofstream(f, std::ios::trunc) << header << "\n";
    expectBad(d.string(), "station_1_horizontal[.]csv:[0-9]+: .*no scans");
  }
  // A config with an unknown key or a bad method name.
  {
    const fs::path config = dir_ / "bad_config.yaml";
    std::ofstream(config) << "registration: {methd: none}\n";
    expectBad(scans().string() + " -c " + config.string(),
              "bad_config[.]yaml: registration[.]methd is not a known key");
    std::ofstream(config, std::ios::trunc) << "registration: {method: sgd}\n";
    expectBad(scans().string() + " -c " + config.string(),
              "bad_config[.]yaml: registration[.]method .*'sgd'");
  }
}

}  // namespace
