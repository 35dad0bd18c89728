// The site plan of app/site.h on a small simulated site that crosses tile borders (the
// tile CLI test's block): its sections against a brute-force grouping of the tiles, every
// sortie's clearance against a brute-force distance to every input point, a section
// planned alone against the same section of the site plan, and the refusals (a sortie
// too close to an input point, a tile without a result, a section beyond the site).

#include "uavip/app/site.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "tests/tiling/block_site.h"
#include "uavip/core/error.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/file_digest.h"
#include "uavip/io/scene_json.h"

namespace {

namespace fs = std::filesystem;
using uavip::InputError;
using uavip::PointList;
using uavip::Vec3;
namespace app = uavip::app;
namespace io = uavip::io;
namespace tiling = uavip::tiling;

/// Distance from p to the segment [a, b] [m], written out here.
double segmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

/// The smallest distance from the path to any of the points [m], by brute force.
double bruteClearance(const PointList& path, const PointList& points) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
    for (const Vec3& p : points) best = std::min(best, segmentDistance(p, path[i], path[i + 1]));
  return best;
}

/// Stages and commits a tile's scene.json with its clouds, as `uavip run-tile` does.
void writeTileScene(const app::TileDetectResult& r) {
  io::ensureDirectory(r.out);
  io::StagedOutputs outputs;
  const std::string pcd = (fs::path(r.out) / "cloud_clean.pcd").string();
  outputs.writeWith(pcd, [&](const std::string& tmp) {
    io::writeCloudPcdFile(tmp, r.detected.scene.cloud, pcd);
  });
  const std::string safety = (fs::path(r.out) / io::kSafetyCloudFile).string();
  outputs.writeWith(safety, [&](const std::string& tmp) {
    io::writeCloudPcdFile(tmp, r.detected.scene.safety->points, safety);
  });
  outputs.write((fs::path(r.out) / "scene.json").string(),
                io::sceneJsonText(r.detected.scene, app::sceneExtras(r.detected, &r.read)));
  outputs.commit();
}

class SiteTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("uavip_site_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    points_ = uavip::test::writeBlockSite(dir_ / "site.xyz");
    config_ = app::parseConfig(
        "camera: {footprint_m: [3.0, 2.0]}\ncoverage: {standoff_m: 2.0}\n"
        "perception: {min_area_m2: 4.0}\n",
        "site.yaml");
    const tiling::TileOptions options = app::siteTileOptions(config_, 15.0, std::nullopt, "");
    const std::string tiles = (dir_ / "T").string();
    io::StagedOutputs staged;
    tiling::Manifest m = tiling::tileCloud(p("site.xyz"), config_.input, options, tiles, staged);
    m.input_sha256 = io::sha256File(p("site.xyz"));
    staged.write(p("T/manifest.json"), tiling::manifestJsonText(m));
    staged.commit();
    manifest_ = tiling::loadManifest(p("T/manifest.json"));
    for (std::size_t i = 0; i < manifest_.tiles.size(); ++i)
      writeTileScene(app::detectTile(manifest_, static_cast<long>(i), config_));
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string p(const std::string& name) { return (dir_ / name).string(); }

  static inline fs::path dir_;
  static inline PointList points_;
  static inline app::Config config_;
  static inline tiling::Manifest manifest_;
};

TEST_F(SiteTest, SectionsAreTheBlocksOfKByKTileCells) {
  ASSERT_EQ(manifest_.tiles.size(), 4U);  // 50 m / 15 m columns, one row
  for (int k = 1; k <= 4; ++k) {
    const auto sections = app::siteSections(manifest_, k);
    // Brute force: tiles share a section exactly when their cells share a K x K block.
    std::map<std::size_t, std::size_t> section_of;
    for (std::size_t s = 0; s < sections.size(); ++s)
      for (const std::size_t t : sections[s]) EXPECT_TRUE(section_of.emplace(t, s).second) << t;
    ASSERT_EQ(section_of.size(), manifest_.tiles.size()) << "K " << k;
    for (std::size_t a = 0; a < manifest_.tiles.size(); ++a)
      for (std::size_t b = 0; b < manifest_.tiles.size(); ++b) {
        const auto& ta = manifest_.tiles[a];
        const auto& tb = manifest_.tiles[b];
        const bool same_block = ta.row / k == tb.row / k && ta.column / k == tb.column / k;
        EXPECT_EQ(section_of[a] == section_of[b], same_block)
            << "K " << k << ": " << a << ", " << b;
      }
  }
  // Far below 2 M points: the whole site is one section.
  EXPECT_EQ(app::siteSections(manifest_, 0).size(), 1U);
  EXPECT_EQ(app::sectionFolder(p("out"), 0, 1), p("out"));
  EXPECT_EQ(app::sectionFolder(p("out"), 7, 9), p("out/section_007"));
}

TEST_F(SiteTest, EverySortieKeepsClearOfEveryInputPointByBruteForce) {
  app::SiteOptions options;
  options.out = p("out");
  std::size_t handed = 0;
  const app::SiteResult site =
      app::planSite(manifest_, config_, options, [&](const app::SectionPlan& s) {
        ++handed;
        EXPECT_TRUE(s.alone());
        EXPECT_EQ(s.out, p("out"));
        EXPECT_EQ(s.tiles.size(), manifest_.tiles.size());
      });
  EXPECT_EQ(handed, 1U);
  ASSERT_EQ(site.sections.size(), 1U);
  EXPECT_EQ(site.input_points, points_.size());
  EXPECT_DOUBLE_EQ(site.required_clearance_m, config_.uav.inflationRadius());
  ASSERT_TRUE(site.flyable());
  const app::SectionSummary& s = site.sections[0];
  ASSERT_TRUE(s.flyable) << s.flight.reason;
  ASSERT_EQ(s.min_clearance_to_input_m.size(), s.flight.sorties.size());
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < s.flight.sorties.size(); ++i) {
    const double brute = bruteClearance(s.flight.sorties[i].waypoints, points_);
    EXPECT_GE(brute, site.required_clearance_m) << "sortie " << i + 1;
    // The input was written with 10 significant digits: 1e-6 m here.
    EXPECT_NEAR(s.min_clearance_to_input_m[i], brute, 1e-4) << "sortie " << i + 1;
    least = std::min(least, brute);
  }
  EXPECT_NEAR(site.min_clearance_m, least, 1e-4);
  // site.json (written for several sections) names the same numbers.
  const auto json = nlohmann::json::parse(app::siteJsonText(manifest_, site));
  ASSERT_EQ(json["sections"].size(), 1U);
  EXPECT_EQ(json["sections"][0]["folder"], "out");
  EXPECT_EQ(json["input_points"].get<std::size_t>(), points_.size());
  EXPECT_NEAR(json["sections"][0]["min_clearance_to_input_m"].get<double>(), least, 1e-3);
  EXPECT_EQ(json["sections"][0]["sorties"].get<std::size_t>(), s.flight.sorties.size());
}

TEST_F(SiteTest, ASectionPlannedAloneIsTheSitePlansSection) {
  app::SiteOptions options;
  options.section_tiles = 2;
  options.out = p("sections");
  std::vector<uavip::planning::FlightPlan> flights;
  std::vector<std::size_t> surfaces;
  const app::SiteResult site =
      app::planSite(manifest_, config_, options, [&](const app::SectionPlan& s) {
        EXPECT_EQ(s.count, 2U);
        EXPECT_EQ(s.out, app::sectionFolder(p("sections"), s.index, 2));
        flights.push_back(s.planned.flight);
        surfaces.push_back(s.detected.scene.surfaces.size());
      });
  ASSERT_EQ(site.sections.size(), 2U);
  ASSERT_EQ(flights.size(), 2U);
  for (std::size_t i = 0; i < 2; ++i) {
    const app::SectionPlan alone = app::planSection(manifest_, config_, i, options);
    EXPECT_EQ(alone.index, i);
    EXPECT_EQ(alone.detected.scene.surfaces.size(), surfaces[i]);
    ASSERT_EQ(alone.planned.flight.sorties.size(), flights[i].sorties.size()) << i;
    for (std::size_t s = 0; s < flights[i].sorties.size(); ++s)
      EXPECT_EQ(alone.planned.flight.sorties[s].waypoints, flights[i].sorties[s].waypoints)
          << "section " << i << ", sortie " << s + 1;
    // Its sorties keep clear of every input point, including those past its border.
    for (const auto& sortie : alone.planned.flight.sorties)
      EXPECT_GE(bruteClearance(sortie.waypoints, points_), config_.uav.inflationRadius());
  }
  EXPECT_THROW(app::planSection(manifest_, config_, 2, options), InputError);
}

TEST_F(SiteTest, AnInputPointOnASortieIsRefusedNamingIt) {
  // The same tiles, but the input has one more point, on the first sortie's first leg.
  app::SiteOptions options;
  options.out = p("out_close");
  const app::SiteResult site = app::planSite(manifest_, config_, options);
  ASSERT_FALSE(site.sections[0].flight.sorties.empty());
  const PointList& path = site.sections[0].flight.sorties[0].waypoints;
  ASSERT_GE(path.size(), 2U);
  const Vec3 on_leg = 0.5 * (path[0] + path[1]);
  fs::copy_file(dir_ / "site.xyz", dir_ / "close.xyz", fs::copy_options::overwrite_existing);
  {
    std::ofstream more(dir_ / "close.xyz", std::ios::app);
    more.precision(10);
    more << on_leg.x() << " " << on_leg.y() << " " << on_leg.z() << "\n";
  }
  tiling::Manifest changed = manifest_;
  changed.input = p("close.xyz");
  changed.input_sha256 = io::sha256File(changed.input);
  try {
    app::planSite(changed, config_, options);
    ADD_FAILURE() << "a sortie through an input point was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sortie 1 comes 0.000 m"), std::string::npos) << e.what();
  }
}

TEST_F(SiteTest, IndexedClearanceEqualsBruteForceNearAndFar) {
  // The points as read back (the file holds them rounded); chunks of 500 points.
  const PointList read = io::loadCloud(p("site.xyz"));
  const app::SiteResult site = [&] {
    app::SiteOptions options;
    options.out = p("out_index");
    return app::planSite(manifest_, config_, options);
  }();
  uavip::planning::FlightPlan planned = site.sections[0].flight;
  ASSERT_FALSE(planned.sorties.empty());
  uavip::planning::FlightPlan extra;
  extra.sorties.resize(4);
  extra.sorties[0].waypoints = {Vec3(25.0, 200.0, 5.0), Vec3(30.0, 260.0, 5.0)};  // far off
  extra.sorties[1].waypoints = {Vec3(-5.0, -5.0, 3.0)};                           // one point
  extra.sorties[2].waypoints = {Vec3(-40.0, 5.0, 2.0), Vec3(90.0, 5.0, 2.0)};     // across all
  const std::vector<const uavip::planning::FlightPlan*> flights{&planned, &extra};
  // Each cutoff read in two passes (the frame found) and in one (the frame given).
  const Vec3 frame = Vec3::Zero();
  for (const double cutoff : {0.5, 3.0, 40.0, -0.5, -3.0, -40.0}) {
    std::uint64_t points = 0;
    Vec3 origin = Vec3::Constant(1.0);
    const auto clear =
        app::clearanceToCloud(p("site.xyz"), config_.input, flights, std::abs(cutoff), 500, &origin,
                              &points, cutoff < 0.0 ? &frame : nullptr);
    EXPECT_EQ(points, read.size());
    EXPECT_EQ(origin, Vec3::Zero());
    ASSERT_EQ(clear.size(), 2U);
    for (std::size_t f = 0; f < 2; ++f) {
      ASSERT_EQ(clear[f].size(), flights[f]->sorties.size());
      for (std::size_t s = 0; s < clear[f].size(); ++s) {
        PointList path = flights[f]->sorties[s].waypoints;
        if (path.size() == 1) path.push_back(path[0]);
        const double brute =
            path.empty() ? std::numeric_limits<double>::infinity() : bruteClearance(path, read);
        if (std::isinf(brute))
          EXPECT_TRUE(std::isinf(clear[f][s]));
        else
          EXPECT_NEAR(clear[f][s], brute, 1e-9)
              << "cutoff " << cutoff << ", flight " << f << ", sortie " << s + 1;
      }
    }
  }
}

TEST_F(SiteTest, ASectionResultIsJoinedOnlyWhileItsInputsAreUnchanged) {
  app::SiteOptions options;
  options.section_tiles = 2;
  options.out = p("joined");
  const auto parts = app::siteSections(manifest_, 2);
  ASSERT_EQ(parts.size(), 2U);
  app::SectionKey key;
  key.manifest_sha256 = io::sha256File(manifest_.path);
  key.section_tiles = 2;
  // Section 1's result as plan-section leaves it (its record only: no other file).
  app::SectionPlan plan = app::planSection(manifest_, config_, 1, options);
  const std::string folder = app::sectionResultFolder(manifest_, 1);
  io::writeFileAtomic((fs::path(folder) / app::kSectionResultFile).string(),
                      app::sectionResultJsonText(manifest_, key, plan, {}));
  const app::SectionResult r = app::readSectionResult(manifest_, key, parts, 1, p("joined"));
  ASSERT_TRUE(r.summary) << r.why;
  EXPECT_EQ(r.summary->out, app::sectionFolder(p("joined"), 1, 2));
  ASSERT_EQ(r.summary->flight.sorties.size(), plan.planned.flight.sorties.size());
  for (std::size_t s = 0; s < plan.planned.flight.sorties.size(); ++s)  // bit for bit
    EXPECT_EQ(r.summary->flight.sorties[s].waypoints, plan.planned.flight.sorties[s].waypoints);
  EXPECT_EQ(r.summary->stops, app::summarize(plan).stops);

  // Joined by the site plan (section 0 planned there): the same clearances as when
  // every section is planned there.
  std::vector<std::size_t> planned_here, joined;
  options.results = &key;
  const app::SiteResult site = app::planSite(
      manifest_, config_, options,
      [&](const app::SectionPlan& s) { planned_here.push_back(s.index); }, {},
      [&](const app::SectionResult& j) { joined.push_back(j.index); });
  EXPECT_EQ(planned_here, std::vector<std::size_t>{0});
  EXPECT_EQ(joined, std::vector<std::size_t>{1});
  app::SiteOptions fresh = options;
  fresh.results = nullptr;
  const app::SiteResult all_here = app::planSite(manifest_, config_, fresh);
  ASSERT_EQ(site.sections.size(), 2U);
  for (std::size_t i = 0; i < 2; ++i)
    EXPECT_EQ(site.sections[i].min_clearance_to_input_m,
              all_here.sections[i].min_clearance_to_input_m);

  // Stale: another manifest, another --section-tiles, a tile's result rewritten.
  app::SectionKey other = key;
  other.manifest_sha256 = "0";
  EXPECT_NE(app::readSectionResult(manifest_, other, parts, 1, "").why.find("another manifest"),
            std::string::npos);
  other = key;
  other.section_tiles = 0;
  EXPECT_FALSE(app::readSectionResult(manifest_, other, parts, 1, "").summary);
  const std::string scene =
      (fs::path(manifest_.dir()) / manifest_.tiles[parts[1][0]].out / "scene.json").string();
  const std::string before = io::readFile(scene);
  io::writeFileAtomic(scene, before + " ");
  const app::SectionResult stale = app::readSectionResult(manifest_, key, parts, 1, "");
  EXPECT_FALSE(stale.summary);
  EXPECT_NE(stale.why.find("tile " + std::to_string(parts[1][0])), std::string::npos) << stale.why;
  // Required: refused naming both sections and the command.
  options.require_results = true;
  try {
    app::planSite(manifest_, config_, options);
    ADD_FAILURE() << "a stale section result was joined";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("section(s) 0,1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("uavip plan-section"), std::string::npos) << e.what();
  }
  io::writeFileAtomic(scene, before);
  fs::remove_all(folder);
}

TEST_F(SiteTest, MissingResultsAndBadOptionsAreRefused) {
  tiling::Manifest elsewhere = manifest_;
  fs::create_directories(dir_ / "empty");
  elsewhere.path = p("empty/manifest.json");  // no tile results beside it
  app::SiteOptions options;
  options.out = p("never");
  try {
    app::planSite(elsewhere, config_, options);
    ADD_FAILURE() << "a site without tile results was planned";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no result for tile(s) 0,1,2,3"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(app::planSection(elsewhere, config_, 0, options), InputError);
  options.section_tiles = -1;
  EXPECT_THROW(app::planSite(manifest_, config_, options), InputError);
  EXPECT_FALSE(fs::exists(dir_ / "never"));
  // A buffer below the standoff and the inflation radius cannot see a border stop's leg.
  EXPECT_THROW(app::siteTileOptions(config_, 15.0, 1.0, ""), InputError);
  EXPECT_GE(app::siteTileOptions(config_, 15.0, std::nullopt, "").buffer_m,
            2.0 * app::leastTileBuffer(config_));
}

}  // namespace
