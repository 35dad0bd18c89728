// Views: the PLY and OBJ parsed back and counted against a hand-made scene and
// mission; the overview picture decoded and checked for size and content.

#include "uavip/view/views.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "uavip/render/figure.h"

namespace {

namespace io = uavip::io;
namespace view = uavip::view;
namespace render = uavip::render;
namespace planning = uavip::planning;
using uavip::Vec3;

/// A 2 × 2 m wall in the plane y = 0 (facing −y, points every 0.25 m), a 5-point
/// obstacle, 3 stray points; surface 0 has 2 stops and a 3-waypoint path,
/// surface 7 (not in the scene) is blocked with 1 stop.
struct Fixture {
  uavip::Scene scene;
  std::vector<uavip::planning::SurfaceMission> missions;
  Fixture() {
    uavip::Surface s;
    s.id = 0;
    s.plane.normal = {0.0, -1.0, 0.0};
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; j <= 8; ++j) s.inliers.emplace_back(0.25 * i, 0.0, 0.25 * j);
    s.boundary = {{0, 0, 0}, {2, 0, 0}, {2, 0, 2}, {0, 0, 2}};
    s.centroid = {1.0, 0.0, 1.0};
    s.area_m2 = 4.0;
    scene.surfaces.push_back(s);
    uavip::Obstacle o;
    o.id = 0;
    for (int i = 0; i < 5; ++i) o.points.emplace_back(4.0, 0.1 * i, 0.5);
    scene.obstacles.push_back(o);
    scene.cloud = s.inliers;
    scene.cloud.insert(scene.cloud.end(), o.points.begin(), o.points.end());
    for (int i = 0; i < 3; ++i) scene.cloud.emplace_back(-2.0, 1.0 + i, 0.0);

    uavip::planning::SurfaceMission m;
    m.surface_id = 0;
    m.status = uavip::planning::SurfaceStatus::Ok;
    m.strategy.camera.footprint_w_m = 0.6;
    m.strategy.camera.footprint_h_m = 0.4;
    m.strategy.axis_w = Vec3::UnitX();
    m.strategy.axis_h = Vec3::UnitZ();
    for (int k = 0; k < 2; ++k) {
      uavip::coverage::Stop st;
      st.index = k;
      st.target = {0.5 + k, 0.0, 1.0};
      st.position = {0.5 + k, -1.5, 1.0};
      m.strategy.stops.push_back(st);
    }
    m.stop_problems.assign(2, uavip::planning::StopProblem::None);
    m.waypoints = {{0.5, -1.5, 1.0}, {1.0, -1.6, 1.0}, {1.5, -1.5, 1.0}};
    m.path_length_m = 1.02;
    missions.push_back(m);

    uavip::planning::SurfaceMission b;
    b.surface_id = 7;
    b.status = uavip::planning::SurfaceStatus::Blocked;
    uavip::coverage::Stop st;
    st.position = {9.0, 9.0, 9.0};
    b.strategy.stops.push_back(st);
    b.stop_problems.assign(1, uavip::planning::StopProblem::InObstacleSpace);
    missions.push_back(b);
  }
};

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string l;
  while (std::getline(in, l)) out.push_back(l);
  return out;
}

TEST(Views, PlyHeaderCountsAndColours) {
  const Fixture f;
  const auto ls = lines(view::sceneToPly(f.scene, f.missions));
  ASSERT_GT(ls.size(), 3u);
  EXPECT_EQ(ls[0], "ply");
  EXPECT_EQ(ls[1], "format ascii 1.0");
  std::size_t end = 0, vertices = 0;
  std::vector<std::string> props;
  for (std::size_t i = 0; i < ls.size(); ++i) {
    if (ls[i].rfind("element vertex ", 0) == 0) vertices = std::stoul(ls[i].substr(15));
    if (ls[i].rfind("property ", 0) == 0) props.push_back(ls[i]);
    if (ls[i] == "end_header") {
      end = i;
      break;
    }
  }
  const std::size_t expected = 81 + 5 + 3 + 3;  // wall, obstacle, strays, stops of both missions
  EXPECT_EQ(vertices, expected);
  ASSERT_EQ(ls.size(), end + 1 + expected);
  EXPECT_EQ(props[3], "property uchar red");
  EXPECT_EQ(props[4], "property uchar green");
  EXPECT_EQ(props[5], "property uchar blue");

  const render::Color wall = view::surfaceColor(0);
  std::map<int, int> kinds;
  int wall_coloured = 0, obstacle_coloured = 0;
  for (std::size_t i = end + 1; i < ls.size(); ++i) {
    std::istringstream in(ls[i]);
    double x = 0, y = 0, z = 0;
    int r = 0, g = 0, b = 0, kind = 0, surface = 0;
    ASSERT_TRUE(in >> x >> y >> z >> r >> g >> b >> kind >> surface) << ls[i];
    ++kinds[kind];
    if (kind == 1) {
      EXPECT_DOUBLE_EQ(y, 0.0);  // wall points lie on y = 0
      EXPECT_EQ(surface, 0);
      wall_coloured += r == wall.red8() && g == wall.green8() && b == wall.blue8();
    }
    if (kind == 2) {
      EXPECT_DOUBLE_EQ(x, 4.0);
      obstacle_coloured += r == view::kObstacleColor.red8() && g == view::kObstacleColor.green8();
    }
    if (kind == 0) {
      EXPECT_DOUBLE_EQ(x, -2.0);
    }
  }
  EXPECT_EQ(kinds[1], 81);
  EXPECT_EQ(kinds[2], 5);
  EXPECT_EQ(kinds[0], 3);
  EXPECT_EQ(kinds[3], 3);
  EXPECT_EQ(wall_coloured, 81);
  EXPECT_EQ(obstacle_coloured, 5);
}

TEST(Views, ObjHasOnePolylinePerFlownSurface) {
  const Fixture f;
  const auto ls = lines(view::pathsToObj(f.missions));
  int v = 0, l = 0;
  std::string line;
  for (const auto& s : ls) {
    v += s.rfind("v ", 0) == 0;
    if (s.rfind("l ", 0) == 0) {
      ++l;
      line = s;
    }
  }
  EXPECT_EQ(v, 3);
  EXPECT_EQ(l, 1);  // the blocked surface has no path
  EXPECT_EQ(line, "l 1 2 3");
  // Two flown surfaces: indices continue across objects.
  auto two = f.missions;
  two[1] = two[0];
  two[1].surface_id = 3;
  const auto ls2 = lines(view::pathsToObj(two));
  EXPECT_EQ(ls2.back(), "l 4 5 6");
}

TEST(Views, ObjHasOnePolylinePerSortieOfTheFlight) {
  const Fixture f;
  planning::FlightPlan flight;
  flight.status = planning::FlightPlan::Status::Ok;
  flight.sorties.resize(2);
  flight.sorties[0].waypoints = {{0, 0, 1}, {1, 0, 1}, {0, 0, 1}};
  flight.sorties[1].waypoints = {{0, 0, 1}, {0, 2, 1}, {0, 2, 2}, {0, 0, 1}};
  const auto ls = lines(view::pathsToObj(f.missions, &flight));
  std::vector<std::string> objects, polylines;
  for (const auto& s : ls) {
    if (s.rfind("o ", 0) == 0) objects.push_back(s);
    if (s.rfind("l ", 0) == 0) polylines.push_back(s);
  }
  EXPECT_EQ(objects, (std::vector<std::string>{"o sortie_1", "o sortie_2"}));
  EXPECT_EQ(polylines, (std::vector<std::string>{"l 1 2 3", "l 4 5 6 7"}));
  // A failed flight: the surfaces' own paths.
  flight.status = planning::FlightPlan::Status::Failed;
  EXPECT_EQ(view::pathsToObj(f.missions, &flight), view::pathsToObj(f.missions));
}

/// Pixels with a clear colour (not white, grey or black) left of column x_max.
std::size_t colourful(const render::Raster& r, int x_max) {
  std::size_t n = 0;
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < std::min(x_max, r.width); ++x) {
      const render::Color c = r.at(x, y);
      n += std::max({c.r, c.g, c.b}) - std::min({c.r, c.g, c.b}) > 0.15;
    }
  return n;
}

std::size_t near(const render::Raster& r, const render::Color& want, int x_max) {
  std::size_t n = 0;
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < std::min(x_max, r.width); ++x) {
      const render::Color c = r.at(x, y);
      n += std::abs(c.r - want.r) < 0.03 && std::abs(c.g - want.g) < 0.03 &&
           std::abs(c.b - want.b) < 0.03;
    }
  return n;
}

TEST(Views, OverviewHasTheSizeAndShowsTheMission) {
  const Fixture f;
  view::OverviewOptions o;
  o.width_px = 1000;
  o.height_px = 620;
  const render::Raster full = render::decodePng(view::overviewFigure(f.scene, f.missions, o).png());
  EXPECT_EQ(full.width, 1000);
  EXPECT_EQ(full.height, 620);
  uavip::Scene empty;
  const render::Raster bare = render::decodePng(view::overviewFigure(empty, {}, o).png());
  // The views (left of the legend column, which starts at 78 % of the width) are
  // grey axes when empty and show the coloured wall, stops and path with a scene.
  const int views = static_cast<int>(0.75 * o.width_px);
  EXPECT_EQ(colourful(bare, views), 0u);
  EXPECT_GT(colourful(full, views), 300u);
  EXPECT_GT(near(full, view::surfaceColor(0), views), 10u);  // stops in the wall's colour
  EXPECT_GT(near(full, render::kRed, views), 5u);            // the infeasible stop's cross
}

TEST(Views, WriteViewsWritesItsFourFilesAtomically) {
  const Fixture f;
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("uavip_views_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  view::OverviewOptions o;
  o.width_px = 800;
  o.height_px = 500;
  io::StagedOutputs outputs;
  view::writeViews(outputs, dir.string(), f.scene, f.missions, o);
  EXPECT_FALSE(fs::exists(dir / "overview.png"));  // staged until the command commits
  outputs.commit();
  for (const char* name : {"scene.ply", "path.obj", "overview.png", "mission.html"}) {
    EXPECT_TRUE(fs::exists(dir / name)) << name;
    EXPECT_GT(fs::file_size(dir / name), 100u) << name;
  }
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
  }
  EXPECT_EQ(files, 4u);
  fs::remove_all(dir);
}

}  // namespace
