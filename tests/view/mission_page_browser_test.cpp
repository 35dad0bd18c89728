// The mission page as a user gets it: `uavip run` on the bundled scenario writes
// OUT/mission.html, whose embedded counts equal mission.json's; `uavip view` writes
// the same page and rejects bad input with one line and exit 2; and Debian's headless
// Chromium draws it: the title turns "ready", and a screenshot from the top shows the
// cloud's and the path's colours where the scene and the mission put them.
// Without chromium the browser tests are skipped, naming why.

#include <cairo.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.h"
#include "uavip/io/scene_json.h"
#include "uavip/view/views.h"

namespace {

namespace fs = std::filesystem;
namespace io = uavip::io;
namespace view = uavip::view;
using uavip::Vec3;
using uavip::cli_test::Result;
using uavip::cli_test::slurp;
using uavip::cli_test::uavip;

nlohmann::json readJson(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

/// The text of <script type="application/json" id="ID"> in a page.
nlohmann::json block(const std::string& html, const std::string& id) {
  const std::string open = "<script type=\"application/json\" id=\"" + id + "\">";
  const auto a = html.find(open);
  if (a == std::string::npos) return nullptr;
  const auto b = html.find("</script>", a);
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

/// Runs a shell command; its stdout (stderr is dropped: Chromium logs GPU and D-Bus
/// noise there).
std::string capture(const std::string& cmd) {
  std::string out;
  FILE* pipe = ::popen((cmd + " 2>/dev/null").c_str(), "r");
  if (!pipe) return out;
  std::array<char, 8192> buf{};
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  ::pclose(pipe);
  return out;
}

/// Chromium's path (UAVIP_CHROMIUM, else Debian's), or "" when it is not installed.
std::string chromium() {
  if (const char* env = std::getenv("UAVIP_CHROMIUM"); env != nullptr && *env != '\0')
    return ::access(env, X_OK) == 0 ? env : "";
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (::access(p, X_OK) == 0) return p;
  return "";
}

class MissionPageCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("uavip_page_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const std::string scenario = std::string(UAVIP_SOURCE_DIR) + "/scenarios/single_cube.yaml";
    run_ = uavip("run " + scenario + " -q -o " + (dir_ / "single_cube").string());
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static fs::path out() { return dir_ / "single_cube"; }

  /// Headless Chromium on `page` + `hash` with WebGL on SwiftShader; `mode` is
  /// --dump-dom or --screenshot=FILE.
  static std::string browse(const fs::path& page, const std::string& hash,
                            const std::string& mode) {
    const fs::path profile = dir_ / "profile";
    return capture(chromium() +
                   " --headless --no-sandbox --use-gl=swiftshader --enable-unsafe-swiftshader "
                   "--hide-scrollbars"
                   " --no-first-run --disable-extensions --mute-audio --window-size=1200,800"
                   " --virtual-time-budget=30000 --user-data-dir=" +
                   profile.string() + " " + mode + " 'file://" + page.string() + hash + "'");
  }

  static inline fs::path dir_;
  static inline Result run_;
};

TEST_F(MissionPageCli, RunWritesThePageWithTheMissionsNumbers) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  const std::string html = slurp(out() / "mission.html");
  ASSERT_FALSE(html.empty());
  const nlohmann::json page = block(html, "uavip-summary");
  ASSERT_TRUE(page.is_object());
  const nlohmann::json mission = readJson(out() / "mission.json");
  std::size_t photos = 0, waypoints = 0, flight_waypoints = 0;
  for (const auto& s : mission["surfaces"]) {
    photos += s["stops"].size();
    waypoints += s["waypoints"].size();
  }
  for (const auto& s : mission["flight"]["sorties"]) flight_waypoints += s["waypoints"].size();
  EXPECT_GT(photos, 0u);
  EXPECT_EQ(page["photos"].get<std::size_t>(), photos);
  EXPECT_EQ(page["waypoints"].get<std::size_t>(), waypoints);
  EXPECT_EQ(page["sorties"].get<std::size_t>(), mission["flight"]["sorties"].size());
  EXPECT_EQ(page["sorties"].get<std::size_t>(),
            mission["flight"]["sortie_count"].get<std::size_t>());
  EXPECT_EQ(page["flight_waypoints"].get<std::size_t>(), flight_waypoints);
  EXPECT_EQ(page["surfaces_planned"].get<std::size_t>(), mission["surfaces"].size());
  const uavip::Scene scene = io::loadScene((out() / "scene.json").string());
  EXPECT_EQ(page["scene_surfaces"].get<std::size_t>(), scene.surfaces.size());
}

TEST_F(MissionPageCli, ViewWritesTheSamePage) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  const fs::path copy = dir_ / "view" / "single_cube";
  fs::create_directories(copy);
  for (const char* f : {"mission.json", "scene.json", "cloud_safety.pcd"})
    fs::copy_file(out() / f, copy / f, fs::copy_options::overwrite_existing);
  const Result r = uavip("view " + (copy / "mission.json").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("mission.html"), std::string::npos) << r.out;
  // The same counts as run's page (the cloud itself comes back from scene.json in
  // another order and rounded to 0.1 mm, so the bytes differ).
  const std::string from_run = slurp(out() / "mission.html"),
                    from_view = slurp(copy / "mission.html");
  EXPECT_EQ(block(from_view, "uavip-summary"), block(from_run, "uavip-summary"));
  const nlohmann::json run_data = block(from_run, "uavip-data"),
                       view_data = block(from_view, "uavip-data");
  EXPECT_EQ(view_data["title"], run_data["title"]);
  EXPECT_EQ(view_data["summary_line"], run_data["summary_line"]);
  EXPECT_EQ(view_data["inflation_radius_m"], run_data["inflation_radius_m"]);
  ASSERT_EQ(view_data["paths"].size(), run_data["paths"].size());
  for (std::size_t k = 0; k < run_data["paths"].size(); ++k)
    EXPECT_EQ(view_data["paths"][k]["waypoints"], run_data["paths"][k]["waypoints"])
        << "sortie " << k + 1;
  // Deterministic: the same files make the same bytes.
  const Result again = uavip("view -q " + (copy / "mission.json").string() + " -o " +
                             (dir_ / "again.html").string());
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_TRUE(slurp(dir_ / "again.html") == from_view) << "two views of the same mission differ";
  const Result o =
      uavip("view " + (copy / "mission.json").string() + " -o " + (dir_ / "other.html").string());
  ASSERT_EQ(o.code, 0) << o.out;
  EXPECT_TRUE(fs::exists(dir_ / "other.html"));
}

TEST_F(MissionPageCli, ViewBadInputIsOneLineAndExit2) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  const fs::path lone = dir_ / "lone";
  fs::create_directories(lone);
  fs::copy_file(out() / "mission.json", lone / "mission.json",
                fs::copy_options::overwrite_existing);
  Result r = uavip("view " + (lone / "mission.json").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  EXPECT_NE(r.out.find("scene.json"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(lone / "mission.html"));

  std::ofstream(lone / "scene.json") << R"({"surfaces": [], "obstacles": []})";
  r = uavip("view " + (lone / "mission.json").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  EXPECT_NE(r.out.find("no points"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(lone / "mission.html"));
}

TEST_F(MissionPageCli, NoViewsWritesNoPage) {
  const fs::path o = dir_ / "noviews";
  const Result r = uavip("run " + std::string(UAVIP_SOURCE_DIR) +
                         "/scenarios/single_cube.yaml -q --no-views -o " + o.string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::exists(o / "mission.json"));
  EXPECT_FALSE(fs::exists(o / "mission.html"));
}

// ---- in the browser

/// A decoded screenshot: 0xRRGGBB per pixel.
struct Image {
  int w{0}, h{0};
  std::vector<std::uint32_t> px;
  std::uint32_t at(int x, int y) const {
    return px[static_cast<std::size_t>(y) * w + x] & 0xffffff;
  }
};

Image readPng(const fs::path& p) {
  Image img;
  cairo_surface_t* s = cairo_image_surface_create_from_png(p.c_str());
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
    cairo_surface_flush(s);
    img.w = cairo_image_surface_get_width(s);
    img.h = cairo_image_surface_get_height(s);
    const int stride = cairo_image_surface_get_stride(s);
    const unsigned char* data = cairo_image_surface_get_data(s);
    img.px.resize(static_cast<std::size_t>(img.w) * img.h);
    for (int y = 0; y < img.h; ++y)
      for (int x = 0; x < img.w; ++x)
        img.px[static_cast<std::size_t>(y) * img.w + x] = reinterpret_cast<const std::uint32_t*>(
            data + static_cast<std::ptrdiff_t>(y) * stride)[x];
  }
  cairo_surface_destroy(s);
  return img;
}

std::uint32_t rgb(const uavip::render::Color& c) {
  return (static_cast<std::uint32_t>(c.red8()) << 16) |
         (static_cast<std::uint32_t>(c.green8()) << 8) | c.blue8();
}

bool near(std::uint32_t a, std::uint32_t b, int tol = 8) {
  for (int s = 0; s <= 16; s += 8)
    if (std::abs(static_cast<int>((a >> s) & 255) - static_cast<int>((b >> s) & 255)) > tol)
      return false;
  return true;
}

/// The attribute `name` of the element with id uavip-state in a dumped DOM.
std::string stateAttribute(const std::string& dom, const std::string& name) {
  const auto at = dom.find("id=\"uavip-state\"");
  if (at == std::string::npos) return "";
  const auto start = dom.rfind('<', at);
  const auto end = dom.find('>', at);
  const std::string tag = dom.substr(start, end - start);
  const auto a = tag.find(name + "=\"");
  if (a == std::string::npos) return "";
  const auto b = tag.find('"', a + name.size() + 2);
  return tag.substr(a + name.size() + 2, b - a - name.size() - 2);
}

std::vector<double> numbers(const std::string& s) {
  std::vector<double> v;
  std::istringstream in(s);
  double x = 0.0;
  while (in >> x) v.push_back(x);
  return v;
}

/// World → screenshot pixels with the page's camera (data-matrix, data-origin, data-canvas).
struct Projection {
  std::vector<double> m, origin, canvas;
  bool valid() const { return m.size() == 16 && origin.size() == 3 && canvas.size() == 4; }
  /// x, y [px] and NDC depth (smaller is nearer).
  std::array<double, 3> operator()(const Vec3& p) const {
    const double q[4] = {p.x() - origin[0], p.y() - origin[1], p.z() - origin[2], 1.0};
    double c[4] = {0, 0, 0, 0};
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 4; ++k)
        c[r] += m[static_cast<std::size_t>(k) * 4 + static_cast<std::size_t>(r)] *
                q[k];  // column-major
    return {canvas[0] + (c[0] / c[3] + 1.0) / 2.0 * canvas[2],
            canvas[1] + (1.0 - c[1] / c[3]) / 2.0 * canvas[3], c[2] / c[3]};
  }
};

TEST_F(MissionPageCli, ChromiumDrawsTheTopView) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  if (chromium().empty())
    GTEST_SKIP() << "chromium is not installed (scripts/test.sh installs it; or set "
                    "UAVIP_CHROMIUM): no browser test";
  const fs::path page = out() / "mission.html";
  const std::string hash = "#view=top&layers=cloud,flight&path=sortie&points=all&canvas=900x600";
  const std::string dom = browse(page, hash, "--dump-dom");
  ASSERT_NE(dom.find("<title>ready</title>"), std::string::npos) << dom.substr(0, 400);
  EXPECT_EQ(stateAttribute(dom, "data-view"), "top");
  EXPECT_EQ(stateAttribute(dom, "data-path-mode"), "sortie");
  const Projection proj{numbers(stateAttribute(dom, "data-matrix")),
                        numbers(stateAttribute(dom, "data-origin")),
                        numbers(stateAttribute(dom, "data-canvas"))};
  ASSERT_TRUE(proj.valid()) << dom.substr(0, 400);

  const fs::path png = dir_ / "top.png";
  browse(page, hash, "--screenshot=" + png.string());
  const Image img = readPng(png);
  ASSERT_GT(img.w, 0) << "no screenshot at " << png;

  // The cloud as the page draws it: every stride-th point in its class colour; the
  // nearest point wins a pixel (a z-buffer of the points' centres).
  const uavip::Scene scene = io::loadScene((out() / "scene.json").string());
  const nlohmann::json data = block(slurp(page), "uavip-data");
  const std::size_t stride = data["cloud"]["stride"].get<std::size_t>();
  std::map<std::array<double, 3>, std::uint32_t> colour;
  for (const auto& s : scene.surfaces)
    for (const auto& p : s.inliers) colour[{p.x(), p.y(), p.z()}] = rgb(view::surfaceColor(s.id));
  for (const auto& o : scene.obstacles)
    for (const auto& p : o.points) colour[{p.x(), p.y(), p.z()}] = rgb(view::kObstacleColor);
  std::vector<double> depth(img.px.size(), 2.0);
  std::vector<std::uint32_t> expected(img.px.size(), 0xffffffff);
  for (std::size_t i = 0; i < scene.cloud.size(); i += stride) {
    const Vec3& p = scene.cloud[i];
    const auto s = proj(p);
    const auto c = colour.find({p.x(), p.y(), p.z()});
    const std::uint32_t col = c == colour.end() ? rgb(view::kCloudColor) : c->second;
    // The page draws each point as a square about 1.5 point spacings wide: splat it
    // over 7 × 7 px (gaps between points then do not count as cloud-free).
    for (int dy = -3; dy <= 3; ++dy)
      for (int dx = -3; dx <= 3; ++dx) {
        const int x = static_cast<int>(std::floor(s[0])) + dx,
                  y = static_cast<int>(std::floor(s[1])) + dy;
        if (x < 0 || y < 0 || x >= img.w || y >= img.h) continue;
        const std::size_t k = static_cast<std::size_t>(y) * img.w + x;
        if (s[2] < depth[k]) {
          depth[k] = s[2];
          expected[k] = col;
        }
      }
  }
  // The flight's samples on screen, to leave the cloud test the pixels the path covers.
  const nlohmann::json mission = readJson(out() / "mission.json");
  std::vector<std::uint8_t> near_path(img.px.size(), 0);
  std::vector<std::uint32_t> sortie_colour;
  for (std::size_t k = 0; k < mission["flight"]["sorties"].size(); ++k) {
    sortie_colour.push_back(
        rgb(uavip::render::palette(static_cast<int>(k)).mix(uavip::render::kBlack, 0.35)));
    const auto& w = mission["flight"]["sorties"][k]["waypoints"];
    for (std::size_t j = 0; j + 1 < w.size(); ++j) {
      const Vec3 a(w[j][0].get<double>(), w[j][1].get<double>(), w[j][2].get<double>());
      const Vec3 b(w[j + 1][0].get<double>(), w[j + 1][1].get<double>(), w[j + 1][2].get<double>());
      for (int t = 0; t <= 200; ++t) {
        const auto s = proj(a + (b - a) * (t / 200.0));
        for (int dy = -3; dy <= 3; ++dy)
          for (int dx = -3; dx <= 3; ++dx) {
            const int x = static_cast<int>(s[0]) + dx, y = static_cast<int>(s[1]) + dy;
            if (x >= 0 && y >= 0 && x < img.w && y < img.h)
              near_path[static_cast<std::size_t>(y) * img.w + x] = 1;
          }
      }
    }
  }
  // Cloud: pixels inside a patch of one expected colour (5 × 5), away from the path and
  // from the canvas's corners (scale bar, north arrow, status line).
  int checked = 0, matched = 0;
  const int margin = 80;
  for (int y = static_cast<int>(proj.canvas[1]) + margin; y < img.h - margin; y += 3) {
    for (int x = static_cast<int>(proj.canvas[0]) + margin; x < img.w - margin; x += 3) {
      const std::uint32_t c = expected[static_cast<std::size_t>(y) * img.w + x];
      if (c == 0xffffffff) continue;
      bool uniform = true;
      for (int dy = -2; dy <= 2 && uniform; ++dy)
        for (int dx = -2; dx <= 2 && uniform; ++dx) {
          const std::size_t k = static_cast<std::size_t>(y + dy) * img.w + (x + dx);
          uniform = expected[k] == c && !near_path[k];
        }
      if (!uniform) continue;
      // Points are squares of at most 4 px, so gaps of a pixel or two may show between
      // them: the colour must be within 2 px.
      ++checked;
      bool hit = false;
      for (int dy = -2; dy <= 2 && !hit; ++dy)
        for (int dx = -2; dx <= 2 && !hit; ++dx) hit = near(img.at(x + dx, y + dy), c);
      matched += hit;
    }
  }
  ASSERT_GE(checked, 50) << "too few cloud pixels to check";
  std::cout << "cloud: " << matched << " of " << checked << " pixels in the scene's colours\n";
  EXPECT_GE(matched, 0.9 * checked)
      << matched << " of " << checked << " cloud pixels in the scene's colours";

  // Path: at the middle of every segment longer than 8 px on screen, a sortie colour
  // within 2 px.
  int segments = 0, found = 0;
  std::vector<int> own(sortie_colour.size(), 0);
  for (std::size_t k = 0; k < mission["flight"]["sorties"].size(); ++k) {
    const auto& w = mission["flight"]["sorties"][k]["waypoints"];
    for (std::size_t j = 0; j + 1 < w.size(); ++j) {
      const Vec3 a(w[j][0].get<double>(), w[j][1].get<double>(), w[j][2].get<double>());
      const Vec3 b(w[j + 1][0].get<double>(), w[j + 1][1].get<double>(), w[j + 1][2].get<double>());
      const auto sa = proj(a), sb = proj(b), sm = proj((a + b) / 2.0);
      if (std::hypot(sa[0] - sb[0], sa[1] - sb[1]) < 8.0) continue;
      const int x0 = static_cast<int>(std::lround(sm[0])),
                y0 = static_cast<int>(std::lround(sm[1]));
      if (x0 < 2 || y0 < 2 || x0 >= img.w - 2 || y0 >= img.h - 2) continue;
      ++segments;
      bool any = false, mine = false;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const std::uint32_t c = img.at(x0 + dx, y0 + dy);
          for (const auto sc : sortie_colour) any = any || near(c, sc);
          mine = mine || near(c, sortie_colour[k]);
        }
      found += any;
      own[k] += mine;
    }
  }
  ASSERT_GE(segments, 4) << "too few path segments on screen";
  std::cout << "path: " << found << " of " << segments << " segments in a sortie's colour\n";
  EXPECT_GE(found, 0.9 * segments)
      << found << " of " << segments << " path segments show a sortie's colour";
  for (std::size_t k = 0; k < own.size(); ++k)
    EXPECT_GT(own[k], 0) << "sortie " << k + 1 << "'s colour is nowhere";
}

TEST_F(MissionPageCli, ChromiumOpensEveryView) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  if (chromium().empty())
    GTEST_SKIP() << "chromium is not installed (scripts/test.sh installs it; or set "
                    "UAVIP_CHROMIUM): no browser test";
  for (const char* view : {"orbit", "front", "side"}) {
    const std::string dom =
        browse(out() / "mission.html", std::string("#view=") + view, "--dump-dom");
    EXPECT_NE(dom.find("<title>ready</title>"), std::string::npos)
        << view << ": " << dom.substr(0, 300);
    EXPECT_EQ(stateAttribute(dom, "data-view"), view);
    EXPECT_FALSE(stateAttribute(dom, "data-frame-ms").empty()) << view;
  }
}

/// The text of the element with id `id` in a DOM dump (its first text node).
std::string elementText(const std::string& dom, const std::string& id) {
  const auto at = dom.find("id=\"" + id + "\"");
  if (at == std::string::npos) return "";
  const auto start = dom.find('>', at) + 1;
  return dom.substr(start, dom.find('<', start) - start);
}

// Issue 33: the edit mode. The hash hook drags vertex 2 of the L-shaped wall's boundary
// with pointer events on the canvas and saves; the vertex must land where the pointer
// went (the page's own projection, data-matrix), the saved file must re-plan, and the
// new flight's photo centres must lie in the dragged boundary, some in what it added.
TEST_F(MissionPageCli, ChromiumDragsABoundaryVertexAndTheEditsReplan) {
  if (chromium().empty())
    GTEST_SKIP() << "chromium is not installed (scripts/test.sh installs it; or set "
                    "UAVIP_CHROMIUM): no browser test";
  const fs::path wall = dir_ / "wall_l";
  const Result run = uavip("run " + std::string(UAVIP_SOURCE_DIR) +
                           "/scenarios/wall_l.yaml -q -o " + wall.string());
  ASSERT_EQ(run.code, 0) << run.out;
  const uavip::Scene scene = io::loadScene((wall / "scene.json").string());
  ASSERT_EQ(scene.surfaces.size(), 1u);
  const auto& before = scene.surfaces[0].boundary;
  ASSERT_GT(before.size(), 2u);
  const double dx = 60.0, dy = -40.0;
  const std::string dom =
      browse(wall / "mission.html", "#view=front&canvas=900x600&edit=0:2:60:-40", "--dump-dom");
  ASSERT_NE(dom.find("<title>ready</title>"), std::string::npos) << dom.substr(0, 400);
  EXPECT_EQ(stateAttribute(dom, "data-edit-on"), "true");
  const nlohmann::json after = nlohmann::json::parse(stateAttribute(dom, "data-edit-boundary"));
  ASSERT_EQ(after.size(), before.size());
  const Projection proj{numbers(stateAttribute(dom, "data-matrix")),
                        numbers(stateAttribute(dom, "data-origin")),
                        numbers(stateAttribute(dom, "data-canvas"))};
  ASSERT_TRUE(proj.valid());
  const Vec3 moved(after[2][0].get<double>(), after[2][1].get<double>(), after[2][2].get<double>());
  const auto from = proj(before[2]);
  const auto to = proj(moved);
  EXPECT_NEAR(to[0] - from[0], dx, 1.5);  // where the pointer went, in its plane
  EXPECT_NEAR(to[1] - from[1], dy, 1.5);
  EXPECT_NEAR(scene.surfaces[0].plane.signedDistance(moved), 0.0, 1e-3);

  const std::string yaml = elementText(dom, "edit-yaml");
  ASSERT_NE(yaml.find("uavip-edits: 1"), std::string::npos) << yaml;
  EXPECT_NE(elementText(dom, "edit-cmd").find("--edits edits.yaml"), std::string::npos);
  {
    std::ofstream f(wall / "edits.yaml");
    f << yaml;
  }
  const Result plan =
      uavip("plan " + (wall / "scene.json").string() + " --surface all --edits " +
            (wall / "edits.yaml").string() + " -q -o " + (wall / "edited").string());
  ASSERT_EQ(plan.code, 0) << plan.out;
  const nlohmann::json mission = readJson(wall / "edited" / "mission.json");
  ASSERT_EQ(mission["edits"]["applied"].size(), 1u);
  EXPECT_NE(mission["edits"]["applied"][0].get<std::string>().find("boundary replaced"),
            std::string::npos);
  // The wall lies in y = 0: its boundaries as (x, z) polygons, tested by even-odd rule.
  const auto inside = [](const std::vector<std::array<double, 2>>& poly, double x, double z) {
    bool in = false;
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
      if ((poly[i][1] > z) != (poly[j][1] > z) &&
          x < (poly[j][0] - poly[i][0]) * (z - poly[i][1]) / (poly[j][1] - poly[i][1]) + poly[i][0])
        in = !in;
    }
    return in;
  };
  std::vector<std::array<double, 2>> old_poly, new_poly;
  for (const auto& p : before) old_poly.push_back({p.x(), p.z()});
  for (const auto& p : after) new_poly.push_back({p[0].get<double>(), p[2].get<double>()});
  std::size_t stops = 0, in_new = 0, in_added = 0;
  for (const auto& s : mission["surfaces"]) {
    for (const auto& st : s["stops"]) {
      const double x = st["target"][0].get<double>(), z = st["target"][2].get<double>();
      ++stops;
      in_new += inside(new_poly, x, z);
      in_added += inside(new_poly, x, z) && !inside(old_poly, x, z);
    }
  }
  EXPECT_GT(stops, 0u);
  EXPECT_EQ(in_new, stops) << "every photo centre on the edited boundary";
  EXPECT_GT(in_added, 0u) << "the dragged part of the boundary gets photos";
}

// Issue 45: a fleet's page. Each UAV's sorties in its own colour, and a time slider
// (hash t=SECONDS) that places every UAV where the schedule has it and reports the
// closest approach between two airborne UAVs so far. The reference is independent of
// the page and the planner: the motion recomputed here from mission.json's waypoints,
// photo stops, take-off times and flight model (segments at min(horizontal / cruise,
// vertical / climb or descent), hover + settle at each stop, half the take-off/landing
// time at each end), and the closest approach by sampling every 0.02 s.
struct RefPiece {
  double t0, t1;
  Vec3 a, b;
};

/// Every UAV's motion from mission.json's fleet block, recomputed.
std::vector<std::vector<RefPiece>> referenceMotion(const nlohmann::json& fleet) {
  const auto& m = fleet["model"];
  const double cruise = m["cruise_speed_m_s"].get<double>(),
               climb = m["climb_speed_m_s"].get<double>(),
               descent = m["descent_speed_m_s"].get<double>(),
               stop = m["hover_s"].get<double>() + m["settle_s"].get<double>(),
               half = 0.5 * fleet["options"]["takeoff_landing_s"].get<double>();
  const auto vec3 = [](const nlohmann::json& j) {
    return Vec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
  };
  std::vector<std::vector<RefPiece>> out;
  for (const auto& u : fleet["uavs"]) {
    std::vector<RefPiece> motion;
    for (const auto& s : u["sorties"]) {
      std::vector<Vec3> w;
      for (const auto& p : s["waypoints"]) w.push_back(vec3(p));
      std::vector<int> hovers(w.size(), 0);
      for (const auto& st : s["stops"]) ++hovers.at(st["waypoint"].get<std::size_t>());
      double t = s["start_s"].get<double>();
      const auto stay = [&](const Vec3& p, double dt) {
        motion.push_back({t, t + dt, p, p});
        t += dt;
      };
      stay(w.front(), half);
      for (std::size_t i = 0; i < w.size(); ++i) {
        stay(w[i], hovers[i] * stop);
        if (i + 1 == w.size()) break;
        const Vec3 d = w[i + 1] - w[i];
        const double dt = std::max(std::hypot(d.x(), d.y()) / cruise,
                                   d.z() >= 0.0 ? d.z() / climb : -d.z() / descent);
        motion.push_back({t, t + dt, w[i], w[i + 1]});
        t += dt;
      }
      stay(w.back(), half);
    }
    out.push_back(std::move(motion));
  }
  return out;
}

/// Where a UAV is at t, or nothing when it is on the ground.
std::optional<Vec3> referenceAt(const std::vector<RefPiece>& motion, double t) {
  for (const auto& p : motion) {
    if (t < p.t0 || t > p.t1) continue;
    const double s = p.t1 > p.t0 ? (t - p.t0) / (p.t1 - p.t0) : 0.0;
    return p.a + s * (p.b - p.a);
  }
  return std::nullopt;
}

TEST_F(MissionPageCli, FleetPageReplaysTheScheduleAndTheClosestApproach) {
  const fs::path cube = dir_ / "cube_fleet";
  const Result run = uavip("run " + std::string(UAVIP_SOURCE_DIR) +
                           "/scenarios/single_cube.yaml --uavs 3 -q -o " + cube.string());
  ASSERT_EQ(run.code, 0) << run.out;
  const nlohmann::json mission = readJson(cube / "mission.json");
  const nlohmann::json& fleet = mission["fleet"];
  ASSERT_EQ(fleet["status"], "ok");
  ASSERT_EQ(fleet["uavs"].size(), 3u);
  const std::string html = slurp(cube / "mission.html");
  const nlohmann::json data = block(html, "uavip-data");
  const nlohmann::json summary = block(html, "uavip-summary");
  EXPECT_EQ(summary["uavs"].get<std::size_t>(), 3u);

  // One path per sortie of each UAV, in the UAV's colour; the colours differ.
  std::size_t sorties = 0;
  for (const auto& u : fleet["uavs"]) sorties += u["sorties"].size();
  EXPECT_EQ(summary["sorties"].get<std::size_t>(), sorties);
  ASSERT_EQ(data["paths"].size(), sorties);
  ASSERT_TRUE(data.contains("fleet"));
  std::map<int, std::string> colour;
  std::size_t k = 0;
  for (std::size_t u = 0; u < fleet["uavs"].size(); ++u) {
    const auto& uav = fleet["uavs"][u];
    for (std::size_t s = 0; s < uav["sorties"].size(); ++s, ++k) {
      const auto& path = data["paths"][k];
      EXPECT_EQ(path["uav"].get<std::size_t>(), u + 1);
      EXPECT_EQ(path["waypoint_n"].get<std::size_t>(), uav["sorties"][s]["waypoints"].size());
      EXPECT_EQ(path["color"], data["fleet"]["uavs"][u]["color"]);
    }
    colour[static_cast<int>(u)] = data["fleet"]["uavs"][u]["color"].get<std::string>();
  }
  EXPECT_NE(colour[0], colour[1]);
  EXPECT_NE(colour[0], colour[2]);
  EXPECT_NE(colour[1], colour[2]);

  if (chromium().empty())
    GTEST_SKIP() << "chromium is not installed (scripts/test.sh installs it; or set "
                    "UAVIP_CHROMIUM): no browser test";
  const auto motion = referenceMotion(fleet);
  const double makespan = fleet["makespan_s"].get<double>();
  // Brute force: the least distance between two airborne UAVs at samples 0.02 s apart,
  // as a running minimum; relative speed ≤ 2 × the fastest (cruise, climb, descent) axis
  // combination, so the exact minimum is at most that × 0.01 s below a sample's.
  const double dt = 0.02;
  const auto& m = fleet["model"];
  const double vmax = std::hypot(
      m["cruise_speed_m_s"].get<double>(),
      std::max(m["climb_speed_m_s"].get<double>(), m["descent_speed_m_s"].get<double>()));
  std::vector<double> running;  // running[i]: least up to i·dt
  double least = std::numeric_limits<double>::infinity();
  for (double t = 0.0; t <= makespan + dt; t += dt) {
    std::vector<std::optional<Vec3>> at;
    at.reserve(motion.size());
    for (const auto& mo : motion) at.push_back(referenceAt(mo, t));
    for (std::size_t a = 0; a < at.size(); ++a)
      for (std::size_t b = a + 1; b < at.size(); ++b)
        if (at[a] && at[b]) least = std::min(least, (*at[a] - *at[b]).norm());
    running.push_back(least);
  }
  // 0.1 s before the planner's closest approach: the least so far lies inside a span of
  // two pieces still going on (the page clips it at t).
  const double before_closest = (fleet["closest_approach"]["at_s"].get<double>() - 0.1) / makespan;
  for (const double f : {0.137, 0.41, 0.77, before_closest, 1.0}) {
    const double t = f * makespan;
    const std::string dom =
        browse(cube / "mission.html", "#view=top&t=" + std::to_string(t), "--dump-dom");
    ASSERT_NE(dom.find("<title>ready</title>"), std::string::npos) << dom.substr(0, 400);
    const double page_t = std::stod(stateAttribute(dom, "data-fleet-t"));
    EXPECT_NEAR(page_t, t, 1e-3);
    // Each UAV where the schedule has it, airborne or on the ground.
    std::istringstream rows(stateAttribute(dom, "data-fleet-positions"));
    std::string row;
    std::size_t u = 0;
    for (; std::getline(rows, row, ';'); ++u) {
      const std::vector<double> v = numbers(row);
      ASSERT_EQ(v.size(), 5u) << row;
      ASSERT_LT(u, motion.size());
      EXPECT_EQ(static_cast<std::size_t>(v[0]), u + 1);
      const auto ref = referenceAt(motion[u], page_t);
      EXPECT_EQ(v[4] == 1.0, ref.has_value()) << "uav " << u + 1 << " at t = " << page_t;
      if (ref) {
        EXPECT_LT((Vec3(v[1], v[2], v[3]) - *ref).norm(), 2e-3)
            << "uav " << u + 1 << " at t = " << page_t;
      }
    }
    EXPECT_EQ(u, motion.size());
    // The closest approach so far: no sample closer, none more than the sampling
    // error above; the two UAVs it names are that far apart at the time it names.
    const std::vector<double> c = numbers(stateAttribute(dom, "data-fleet-closest"));
    const std::size_t i = std::min(static_cast<std::size_t>(page_t / dt), running.size() - 1);
    if (!std::isfinite(running[i])) {
      EXPECT_EQ(stateAttribute(dom, "data-fleet-closest"), "none");
      continue;
    }
    ASSERT_EQ(c.size(), 4u) << stateAttribute(dom, "data-fleet-closest");
    std::cout << "t = " << page_t << " s: closest " << c[0] << " m (uav " << c[1] << ", uav "
              << c[2] << ", t = " << c[3] << " s); sampled " << running[i] << " m\n";
    EXPECT_LE(c[0], running[i] + 1e-6);
    EXPECT_GE(c[0], running[i] - 2.0 * vmax * dt);
    EXPECT_LE(c[3], page_t + 1e-3);
    const auto pa = referenceAt(motion.at(static_cast<std::size_t>(c[1]) - 1), c[3]);
    const auto pb = referenceAt(motion.at(static_cast<std::size_t>(c[2]) - 1), c[3]);
    ASSERT_TRUE(pa && pb) << "the closest pair is airborne at its time";
    EXPECT_NEAR((*pa - *pb).norm(), c[0], 2e-3);
    if (f >= 1.0) {  // the whole schedule: the planner's own closest approach
      EXPECT_NEAR(c[0], fleet["closest_approach"]["nominal_m"].get<double>(), 1e-3);
    }
  }
}

// K = 1 (or a mission without a fleet block): the page's data is a single UAV's.
TEST_F(MissionPageCli, OneUavPageHasNoFleet) {
  ASSERT_EQ(run_.code, 0) << run_.out;
  const fs::path one = dir_ / "cube_one";
  const Result r = uavip("run " + std::string(UAVIP_SOURCE_DIR) +
                         "/scenarios/single_cube.yaml --uavs 1 -q -o " + one.string());
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json a = block(slurp(one / "mission.html"), "uavip-data"),
                       b = block(slurp(out() / "mission.html"), "uavip-data");
  EXPECT_FALSE(a.contains("fleet"));
  EXPECT_EQ(a, b);
}

}  // namespace
