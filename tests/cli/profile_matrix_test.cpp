// Every aircraft profile (core/aircraft.h) × the default scenario and two real clouds
// (fcplanner_MBS with --cover structure, autzen_trim by its planes): the plan made for
// the drone exports to DJI WPML without refusal, and the export keeps every photo stop
// of the flight, so nothing is dropped beyond what mission.json reports uncovered (the
// stops the gimbal could not take, counted in their surface's coverage). The numbers of
// benchmarks/README.md ("Aircraft profiles × real clouds") are printed as table rows.
//
// One plan per profile family: m30 and m30t carry the same camera, gimbal, speed, hover
// time and span, so their plans are the same (planned once, exported as both); every
// other profile differs in the camera or the hover time and is planned on its own.
// `generic` is not an aircraft: its plan (a gimbal turning anywhere) goes to a format
// without a gimbal (QGroundControl), and the DJI export of it may refuse, naming the fix.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.h"

namespace {

namespace fs = std::filesystem;
using uavip::cli_test::Result;
using uavip::cli_test::slurp;
using uavip::cli_test::uavip;

const std::string kSource = UAVIP_SOURCE_DIR;

fs::path freshDir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("uavip_profile_matrix_" + name + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// A profile planned once and the drones exported from that plan.
struct Family {
  std::string plan_as;
  std::vector<std::string> export_as;
};

const std::vector<Family>& families() {
  static const std::vector<Family> f = {
      {"m300", {"m300"}}, {"m350", {"m350"}}, {"m30", {"m30", "m30t"}}, {"m3e", {"m3e"}},
      {"m3t", {"m3t"}},   {"m4e", {"m4e"}},   {"m4t", {"m4t"}},         {"generic", {}}};
  return f;
}

/// The sum of "N photo stops" over the export's lines.
int exportedStops(const std::string& out) {
  int total = 0;
  std::istringstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t at = line.find(" photo stops -> ");
    if (line.rfind("exported ", 0) != 0 || at == std::string::npos) continue;
    const std::size_t from = line.rfind(' ', at - 1);
    total += std::stoi(line.substr(from + 1, at - from - 1));
  }
  return total;
}

/// Area of each surface of a scene.json [m²].
std::map<int, double> surfaceAreas(const fs::path& scene) {
  std::map<int, double> out;
  const nlohmann::json j = nlohmann::json::parse(slurp(scene));
  for (const auto& s : j["surfaces"]) out[s["id"].get<int>()] = s["area_m2"].get<double>();
  return out;
}

/// Checks one plan and its exports; prints its table row.
void checkPlan(const std::string& cloud, const Family& family, const fs::path& dir,
               const std::string& export_args) {
  SCOPED_TRACE(cloud + " " + family.plan_as);
  const nlohmann::json m = nlohmann::json::parse(slurp(dir / "mission.json"));
  ASSERT_TRUE(m.contains("flight"));
  const auto& flight = m["flight"];
  int flight_stops = 0;
  for (const auto& s : flight["sorties"]) flight_stops += s["stop_count"].get<int>();
  EXPECT_GT(flight_stops, 0);
  // The stops the gimbal could not take, and what their surfaces report uncovered.
  const std::map<int, double> areas = surfaceAreas(dir / "scene.json");
  int gimbal_dropped = 0;
  double area = 0.0, gimbal_uncovered_m2 = 0.0;
  for (const auto& s : m["surfaces"]) {
    const int id = s["surface_id"].get<int>();
    const auto a = areas.find(id);
    const double surface_m2 = a == areas.end() ? 0.0 : a->second;
    area += surface_m2;
    int dropped = 0;
    for (const auto& st : s["stops"]) dropped += st.value("problem", "") == "gimbal_limit";
    if (dropped == 0) continue;
    gimbal_dropped += dropped;
    const double fraction = s["coverage"]["fraction"].get<double>();
    EXPECT_LT(fraction, 1.0) << "surface " << id << ": gimbal-dropped stops, reported uncovered";
    gimbal_uncovered_m2 += (1.0 - fraction) * surface_m2;
  }
  std::ostringstream gimbal;
  if (m.contains("structure")) {  // the share no view within the gimbal's range images
    const auto& st = m["structure"];
    const double points = st["points"].get<double>();
    gimbal << 100.0 * (1.0 - st["imageable_points"].get<double>() / points)
           << " % of points not imageable; coverage " << 100.0 * st["coverage_rule_b"].get<double>()
           << " %";
  } else {
    gimbal << gimbal_dropped << " stops dropped, " << gimbal_uncovered_m2 << " m2 of " << area
           << " m2 (" << (area > 0 ? 100.0 * gimbal_uncovered_m2 / area : 0.0) << " %)";
  }
  for (const std::string& drone : family.export_as) {
    const Result e = uavip("export " + (dir / "mission.json").string() +
                           " --format dji-kmz --surface all --drone " + drone + export_args +
                           " -o " + (dir / (drone + ".kmz")).string());
    EXPECT_EQ(e.code, 0) << drone << "\n" << e.out;
    EXPECT_EQ(exportedStops(e.out), flight_stops) << drone << "\n" << e.out;
    std::cout << "| " << cloud << " | " << drone << " | " << flight_stops << " | "
              << std::round(flight["length_m"].get<double>() * 10) / 10 << " m | "
              << flight["sortie_count"] << " | " << gimbal.str() << " |\n";
  }
  if (family.export_as.empty()) {  // generic: a format without a gimbal
    const Result e =
        uavip("export " + (dir / "mission.json").string() + " --format qgc-plan --surface all" +
              export_args + " -o " + (dir / "generic.plan").string());
    EXPECT_EQ(e.code, 0) << e.out;
    std::cout << "| " << cloud << " | generic | " << flight_stops << " | "
              << std::round(flight["length_m"].get<double>() * 10) / 10 << " m | "
              << flight["sortie_count"] << " | " << gimbal.str() << " |\n";
  }
}

TEST(ProfileMatrix, DefaultScenario) {
  const fs::path d = freshDir("cube");
  for (const Family& f : families()) {
    const fs::path out = d / f.plan_as;
    const Result r = uavip("-q run " + kSource + "/scenarios/single_cube.yaml --drone " +
                           f.plan_as + " -o " + out.string() + " --no-views");
    ASSERT_EQ(r.code, 0) << f.plan_as << "\n" << r.out;
    checkPlan("single_cube", f, out, " --origin 48,3,100");
  }
}

TEST(ProfileMatrix, FcplannerMbsStructure) {
  const fs::path d = freshDir("mbs");
  const Result det = uavip("-q detect " + kSource + "/tests/data/fcplanner_MBS.pcd -o " +
                           (d / "det").string() + " --no-views");
  ASSERT_EQ(det.code, 0) << det.out;
  for (const Family& f : families()) {
    const fs::path out = d / f.plan_as;
    const Result r =
        uavip("-q plan " + (d / "det" / "scene.json").string() + " --cover structure --drone " +
              f.plan_as + " -o " + out.string() + " --no-views");
    ASSERT_EQ(r.code, 0) << f.plan_as << "\n" << r.out;
    checkPlan("fcplanner_MBS", f, out, " --origin 22.3,114.2,10");
  }
}

TEST(ProfileMatrix, AutzenPlanes) {
  const fs::path d = freshDir("autzen");
  const Result det = uavip("-q detect " + kSource + "/tests/data/autzen_trim.las -o " +
                           (d / "det").string() + " --no-views");
  ASSERT_EQ(det.code, 0) << det.out;
  for (const Family& f : families()) {
    const fs::path out = d / f.plan_as;
    // Exit 3 when some surfaces are blocked (reported in mission.json): the flight
    // over the others is still made.
    const Result r =
        uavip("-q plan " + (d / "det" / "scene.json").string() + " --surface all --drone " +
              f.plan_as + " -o " + out.string() + " --no-views");
    ASSERT_TRUE(r.code == 0 || r.code == 3) << f.plan_as << "\n" << r.out;
    checkPlan("autzen_trim", f, out, "");  // the CRS the LAS file states
  }
}

}  // namespace
