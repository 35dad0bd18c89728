// The photos of a plan (photo/): rays against a brute-force intersection with the
// world's rectangles, the outer surface only, the view centre on the target, the
// COLMAP model re-projecting the targets, PNG bytes independent of the thread count
// and decoding to the rendered pixels, a world that does not match refused; a mesh:
// rays against a brute-force Möller–Trumbore over every triangle, the world as
// triangles rendering as its rectangles do; a cloud preview: splats where the
// projection puts them, nearest first, a PCD's colours in the order of its points; and
// the CLI end to end (run --photos, photos against another world, against the mesh a
// mission was detected from, a preview from the cloud it was detected from); the image
// pairs to match against a brute-force overlap of what the photos see.

#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.h"
#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/text.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/mission_json.h"
#include "uavip/photo/photo_folder.h"
#include "uavip/photo/view_pairs.h"

namespace {

namespace fs = std::filesystem;
using namespace uavip;
using photo::PhotoPose;

/// The tower of scenarios/tower.yaml at a tenth of its size, beside a free wall.
sim::WorldModel towerWorld() {
  sim::WorldModel w;
  w.addBox("shaft", Vec3(-0.3, -0.3, 0.0), Vec3(0.3, 0.3, 4.0));
  w.addBox("platform", Vec3(-0.5, -0.5, 3.0), Vec3(0.5, 0.5, 3.1));
  w.addPlane({"ground", Vec3(-2, -2, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)});
  w.addPlane({"wall", Vec3(1.0, -1.0, 0.2), Vec3(0, 2, 0), Vec3(0, 0, 1.5)});
  return w;
}

/// Brute force: the nearest rectangle a ray meets, in double (t = inf when none).
double bruteForceHit(const sim::WorldModel& w, const Vec3& o, const Vec3& d, Vec3* point) {
  double best = kInf;
  for (const auto& r : w.rects()) {
    const Vec3 n = r.normal();
    const double along = n.dot(d);
    if (std::abs(along) < 1e-12) continue;
    const double t = n.dot(r.corner - o) / along;
    if (!(t > 1e-9 && t < best)) continue;
    const Vec3 q = o + t * d - r.corner;
    const double s = q.dot(r.edge_u) / r.edge_u.squaredNorm();
    const double u = q.dot(r.edge_v) / r.edge_v.squaredNorm();
    if (s < -1e-9 || s > 1 + 1e-9 || u < -1e-9 || u > 1 + 1e-9) continue;
    best = t;
    *point = o + t * d;
  }
  return best;
}

/// The view from `standoff` off `target` along `normal`, looking back at it.
coverage::ViewPose viewAt(const Vec3& target, const Vec3& normal, double standoff) {
  coverage::ViewPose v;
  v.position = target + standoff * normal;
  const Vec3 f = -normal;
  v.yaw_deg = std::atan2(f.y(), f.x()) * kRadToDeg;
  v.pitch_deg = std::asin(std::clamp(f.z(), -1.0, 1.0)) * kRadToDeg;
  return v;
}

coverage::PinholeIntrinsics smallCamera() {
  coverage::PinholeIntrinsics k;
  k.width_px = 96;
  k.height_px = 64;
  k.fx_px = 80.0;
  k.fy_px = 82.0;
  k.cx_px = 47.0;
  k.cy_px = 33.5;
  return k;
}

/// Views of the tower world from every side, some tilted.
std::vector<coverage::ViewPose> towerViews() {
  std::vector<coverage::ViewPose> views;
  views.push_back(viewAt(Vec3(0.3, 0.0, 2.0), Vec3::UnitX(), 1.2));
  views.push_back(viewAt(Vec3(0.0, -0.5, 3.05), -Vec3::UnitY(), 1.5));
  views.push_back(viewAt(Vec3(0.4, 0.4, 3.1), Vec3(0.3, 0.2, 1.0).normalized(), 1.0));
  views.push_back(viewAt(Vec3(0.0, 0.4, 2.9), Vec3(0.0, 0.5, -0.6).normalized(), 0.9));
  views.push_back(viewAt(Vec3(1.0, 0.0, 1.0), -Vec3::UnitX(), 0.6));
  return views;
}

TEST(RayCaster, PixelRaysHitWhatBruteForceFinds) {
  const sim::WorldModel world = towerWorld();
  const photo::RayCaster caster(world);
  const auto k = smallCamera();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(0.0, k.width_px), uy(0.0, k.height_px);
  int hits = 0;
  for (const auto& view : towerViews()) {
    const PhotoPose pose = photo::poseFromView(view);
    for (int i = 0; i < 200; ++i) {
      const Vec3 d = photo::pixelRay(k, pose, ux(rng), uy(rng));
      Vec3 expected = Vec3::Zero();
      const double t = bruteForceHit(world, pose.position, d, &expected);
      const photo::RayHit hit = caster.cast(pose.position, d);
      ASSERT_EQ(hit.hit, std::isfinite(t));
      if (!hit.hit) continue;
      ++hits;
      EXPECT_NEAR(hit.t, t, 1e-4);
      EXPECT_LT((hit.point - expected).norm(), 1e-4);
      EXPECT_LT(world.distanceToTruth(hit.point), 1e-6);
    }
  }
  EXPECT_GT(hits, 500);
}

TEST(RayCaster, SeesOnlyTheOuterSurface) {
  // The platform's faces inside the shaft and the shaft's inside the platform are
  // never hit from outside.
  const sim::WorldModel world = towerWorld();
  const photo::RayCaster caster(world);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto insideBox = [](const Vec3& p, const Vec3& lo, const Vec3& hi) {
    return ((p.array() > lo.array() + 1e-6) && (p.array() < hi.array() - 1e-6)).all();
  };
  int near_tower = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 from(2.0 * u(rng), 2.0 * u(rng), 3.05 + 1.5 * u(rng));
    if (insideBox(from, Vec3(-0.5, -0.5, 3.0), Vec3(0.5, 0.5, 3.1)) ||
        insideBox(from, Vec3(-0.3, -0.3, 0.0), Vec3(0.3, 0.3, 4.0)))
      continue;
    const Vec3 to(0.5 * u(rng), 0.5 * u(rng), 3.05 + 0.3 * u(rng));
    const photo::RayHit hit = caster.cast(from, (to - from).normalized());
    if (!hit.hit) continue;
    const bool in_platform = insideBox(hit.point, Vec3(-0.5, -0.5, 3.0), Vec3(0.5, 0.5, 3.1));
    const bool in_shaft = insideBox(hit.point, Vec3(-0.3, -0.3, 0.0), Vec3(0.3, 0.3, 4.0));
    EXPECT_FALSE(in_platform || in_shaft) << formatPoint(hit.point);
    near_tower += hit.point.head<2>().norm() < 0.75 ? 1 : 0;
  }
  EXPECT_GT(near_tower, 1000);
}

TEST(Renderer, ViewCentreLandsOnTheTarget) {
  const sim::WorldModel world = towerWorld();
  const photo::RayCaster caster(world);
  const auto k = smallCamera();
  const std::vector<Vec3> targets = {Vec3(0.3, 0.0, 2.0), Vec3(0.0, -0.5, 3.05),
                                     Vec3(0.4, 0.4, 3.1), Vec3(1.0, 0.0, 1.0)};
  const std::vector<Vec3> normals = {Vec3::UnitX(), -Vec3::UnitY(),
                                     Vec3(0.3, 0.2, 1.0).normalized(), -Vec3::UnitX()};
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const PhotoPose pose = photo::poseFromView(viewAt(targets[i], normals[i], 0.6));
    const photo::RayHit hit =
        caster.cast(pose.position, photo::pixelRay(k, pose, k.cx_px, k.cy_px));
    ASSERT_TRUE(hit.hit);
    EXPECT_LT((hit.point - targets[i]).norm(), 1e-6) << i;
    const Eigen::Vector3d px = photo::projectToImage(k, pose, targets[i]);
    EXPECT_NEAR(px.x(), k.cx_px, 1e-9);
    EXPECT_NEAR(px.y(), k.cy_px, 1e-9);
    EXPECT_NEAR(px.z(), 0.6, 1e-9);
  }
}

/// A two-surface mission over the tower world in two sorties, footprint camera.
io::MissionRecord towerMission() {
  io::MissionRecord m;
  coverage::Camera cam;
  cam.footprint_w_m = 0.06;
  cam.footprint_h_m = 0.04;
  m.camera = cam;
  m.source = "tower_small.yaml";
  io::SurfaceRecord a, b;
  a.surface_id = 0;
  a.status = "ok";
  a.standoff_m = 0.5;
  b.surface_id = 4;
  b.kind = "structure";
  b.status = "ok";
  b.standoff_m = 0.5;
  const auto stop = [](const Vec3& target, const Vec3& n) {
    io::StopRecord s;
    const auto v = viewAt(target, n, 0.5);
    s.position = v.position;
    s.yaw_deg = v.yaw_deg;
    s.gimbal_pitch_deg = v.pitch_deg;
    s.target = target;
    return s;
  };
  for (int i = 0; i < 3; ++i)
    a.stops.push_back(stop(Vec3(0.3, -0.1 + 0.1 * i, 2.0), Vec3::UnitX()));
  for (int i = 0; i < 2; ++i)
    b.stops.push_back(stop(Vec3(0.45, -0.2 + 0.4 * i, 3.1), Vec3(0.2, 0.0, 1.0).normalized()));
  m.surfaces = {a, b};
  io::FlightRecord f;
  f.status = "ok";
  io::SortieRecord s1, s2;
  s1.stops = {{0, 2, 1}, {0, 1, 2}, {4, 0, 3}};
  s2.stops = {{4, 1, 1}, {0, 0, 2}};
  f.sorties = {s1, s2};
  m.flight = f;
  return m;
}

/// The folder written with `threads` workers (file name → bytes).
std::map<std::string, std::string> writeFolder(const io::MissionRecord& m,
                                               const sim::WorldModel& world, int threads,
                                               const fs::path& dir, double image_scale = 1.0) {
  photo::PhotoOptions o;
  o.threads = threads;
  o.image_scale = image_scale;
  photo::writePhotoFolder(m, "mission.json", world, "tower_small.yaml", dir.string(), o);
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file())
      files[fs::relative(e.path(), dir).string()] = uavip::cli_test::slurp(e.path());
  }
  return files;
}

fs::path tempDir(const std::string& name) {
  fs::path d =
      fs::temp_directory_path() / ("uavip_photo_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

TEST(PhotoFolder, FlownOrderIdsAndCamera) {
  const auto m = towerMission();
  const photo::PhotoCamera cam = photo::photoCamera(m, "mission.json");
  EXPECT_EQ(cam.intrinsics.width_px, 120);  // 0.06 m at 0.5 mm/px
  EXPECT_EQ(cam.intrinsics.height_px, 80);
  EXPECT_NEAR(cam.gsd_m_per_px, photo::kFootprintPixelM, 1e-12);
  const auto photos = photo::plannedPhotos(m, cam, "mission.json");
  ASSERT_EQ(photos.size(), 5U);
  const std::vector<std::string> ids = {"s0_002", "s0_001", "s4_000", "s4_001", "s0_000"};
  for (std::size_t i = 0; i < ids.size(); ++i) {
    EXPECT_EQ(photos[i].stop_id, ids[i]);
    EXPECT_EQ(photos[i].order, i + 1);
    EXPECT_EQ(photos[i].sortie, i < 3 ? 1 : 2);
    EXPECT_NEAR(photos[i].footprint_w_m, 0.06, 1e-9);
  }
  EXPECT_EQ(photos[2].surface_id, -1);  // a structure view
  EXPECT_EQ(photos[0].surface_id, 0);
}

/// Decodes a PNG (libpng's simplified API) to 8-bit RGB.
std::vector<std::uint8_t> decodePng(const std::string& bytes, int* w, int* h) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size())) return {};
  image.format = PNG_FORMAT_RGB;
  std::vector<std::uint8_t> rgb(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, rgb.data(), 0, nullptr)) return {};
  *w = static_cast<int>(image.width);
  *h = static_cast<int>(image.height);
  return rgb;
}

TEST(PhotoFolder, SameBytesWithOneAndTwoThreadsAndPngsDecodeToTheRender) {
  const auto m = towerMission();
  const sim::WorldModel world = towerWorld();
  const fs::path d1 = tempDir("t1"), d2 = tempDir("t2");
  const auto one = writeFolder(m, world, 1, d1);
  const auto two = writeFolder(m, world, 2, d2);
  EXPECT_EQ(one.size(), 11U);  // 5 images, 3 sparse files, pairs.txt, poses.csv, photos.json
  EXPECT_TRUE(one == two);
  // The PNG holds the rendered pixels, and they show texture (not one colour).
  const photo::RayCaster caster(world);
  const photo::PhotoCamera cam = photo::photoCamera(m, "mission.json");
  photo::TextureOptions t;
  t.finest_feature_m = photo::kFinestFeaturePx * cam.gsd_m_per_px;
  const photo::SurfaceTexture texture(t);
  const auto photos = photo::plannedPhotos(m, cam, "mission.json");
  const photo::Image img = photo::renderPhoto(caster, texture, cam.intrinsics, photos[0].pose);
  int w = 0, h = 0;
  const auto decoded = decodePng(one.at("images/s0_002.png"), &w, &h);
  EXPECT_EQ(w, 120);
  EXPECT_EQ(h, 80);
  EXPECT_TRUE(decoded == img.rgb);
  double sum = 0, sum2 = 0;
  for (std::size_t i = 0; i < img.rgb.size(); i += 3) {
    sum += img.rgb[i];
    sum2 += double(img.rgb[i]) * img.rgb[i];
  }
  const double n = static_cast<double>(img.rgb.size()) / 3.0;
  EXPECT_GT(std::sqrt(sum2 / n - (sum / n) * (sum / n)), 10.0);  // grey levels vary
  fs::remove_all(d1);
  fs::remove_all(d2);
}

/// COLMAP's images.txt and cameras.txt read back: every target projects to the
/// principal point at the planned standoff.
TEST(PhotoFolder, ColmapModelReprojectsTheTargetsToTheCentre) {
  const auto m = towerMission();
  const photo::PhotoCamera cam = photo::photoCamera(m, "mission.json");
  const auto photos = photo::plannedPhotos(m, cam, "mission.json");
  std::istringstream cams(photo::colmapCameras(cam));
  std::string line;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  while (std::getline(cams, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    int id = 0, w = 0, h = 0;
    std::string model;
    ls >> id >> model >> w >> h >> fx >> fy >> cx >> cy;
    EXPECT_EQ(model, "PINHOLE");
    EXPECT_EQ(w, 120);
  }
  std::istringstream imgs(photo::colmapImages(photos));
  std::size_t count = 0;
  while (std::getline(imgs, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::size_t id = 0;
    int camera_id = 0;
    double qw, qx, qy, qz, tx, ty, tz;
    std::string name;
    ls >> id >> qw >> qx >> qy >> qz >> tx >> ty >> tz >> camera_id >> name;
    ASSERT_EQ(id, count + 1);
    const auto& p = photos[count++];
    EXPECT_EQ(name, p.stop_id + ".png");
    const Eigen::Matrix3d r = Eigen::Quaterniond(qw, qx, qy, qz).toRotationMatrix();
    const Vec3 c = r * p.target + Vec3(tx, ty, tz);
    EXPECT_NEAR(fx * c.x() / c.z() + cx, 60.0, 1e-6);
    EXPECT_NEAR(fy * c.y() / c.z() + cy, 40.0, 1e-6);
    EXPECT_NEAR(c.z(), 0.5, 1e-6);
    // The camera centre −Rᵀt is the stop's position.
    EXPECT_LT((-(r.transpose() * Vec3(tx, ty, tz)) - p.view.position).norm(), 1e-6);
  }
  EXPECT_EQ(count, photos.size());
}

/// --image-scale: the same views through a pinhole scaled with the image, so every
/// target still projects to the principal point and the footprints do not change; the
/// folder's PNGs have the scaled size and photos.json records the scaled camera.
TEST(PhotoFolder, ImageScaleKeepsTheViewsAndScalesThePinhole) {
  const auto m = towerMission();
  const photo::PhotoCamera full = photo::photoCamera(m, "mission.json");
  const photo::PhotoCamera half = photo::photoCamera(m, "mission.json", 0.5);
  EXPECT_EQ(half.intrinsics.width_px, 60);
  EXPECT_EQ(half.intrinsics.height_px, 40);
  EXPECT_NEAR(half.intrinsics.fx_px, 0.5 * full.intrinsics.fx_px, 1e-9);
  EXPECT_NEAR(half.intrinsics.cy_px, 0.5 * full.intrinsics.cy_px, 1e-9);
  EXPECT_NEAR(half.gsd_m_per_px, 2.0 * full.gsd_m_per_px, 1e-12);
  const auto a = photo::plannedPhotos(m, full, "mission.json");
  const auto b = photo::plannedPhotos(m, half, "mission.json");
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_LT((a[i].pose.position - b[i].pose.position).norm(), 1e-12);
    EXPECT_NEAR(a[i].footprint_w_m, b[i].footprint_w_m, 1e-12);
    // The target through the scaled pinhole: the principal point.
    const Vec3 c = b[i].pose.camera_to_world.transpose() * (b[i].target - b[i].pose.position);
    EXPECT_NEAR(half.intrinsics.fx_px * c.x() / c.z() + half.intrinsics.cx_px, 30.0, 1e-6);
    EXPECT_NEAR(half.intrinsics.fy_px * c.y() / c.z() + half.intrinsics.cy_px, 20.0, 1e-6);
  }
  const fs::path d = tempDir("scale");
  const auto files = writeFolder(m, towerWorld(), 1, d, 0.5);
  int w = 0, h = 0;
  EXPECT_FALSE(decodePng(files.at("images/s0_002.png"), &w, &h).empty());
  EXPECT_EQ(w, 60);
  EXPECT_EQ(h, 40);
  EXPECT_NE(files.at("photos.json").find("\"width_px\": 60"), std::string::npos);
  fs::remove_all(d);
  for (const double bad : {0.0, -0.5, 1.5, std::nan("")})
    EXPECT_THROW(photo::photoCamera(m, "mission.json", bad), InputError) << bad;
}

TEST(PhotoFolder, RefusesAWorldTheMissionWasNotPlannedOn) {
  const auto m = towerMission();
  sim::WorldModel other;
  other.addBox("shaft", Vec3(-0.3, -0.3, 0.0), Vec3(0.3, 0.3, 1.0));  // a shorter tower
  const fs::path d = tempDir("other");
  try {
    writeFolder(m, other, 1, d);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("not planned on this world"), std::string::npos) << msg;
    EXPECT_NE(msg.find("tower_small.yaml"), std::string::npos) << msg;
  }
  EXPECT_FALSE(fs::exists(d / "photos.json"));
}

/// A 2 x 1.5 m wall scenario with a small pinhole camera, written into `dir`.
fs::path writeSmallWall(const fs::path& dir) {
  fs::path scenario = dir / "small_wall.yaml";
  std::ofstream(scenario)
      << "name: small_wall\n"
         "world:\n"
         "  - {type: plane, name: wall, corner: [0.0, 0.0, 0.5], edge_u: [2.0, 0.0, 0.0], "
         "edge_v: [0.0, 0.0, 1.5]}\n"
         "sensing: {mode: sample, spacing_m: 0.05, noise_sigma_m: 0.005, outlier_fraction: 0.0, "
         "seed: 3, viewpoint: [1.0, -4.0, 1.2]}\n"
         "perception: {min_area_m2: 1.0}\n"
         "camera: {fx: 200, fy: 200, cx: 80, cy: 60, image_px: [160, 120], gsd_mm_per_px: 5}\n";
  return scenario;
}

TEST(PhotosCli, RunWithPhotosAndAnotherWorld) {
  const fs::path dir = tempDir("cli");
  fs::create_directories(dir);
  const fs::path scenario = writeSmallWall(dir);
  const auto run = uavip::cli_test::uavip("run " + scenario.string() +
                                          " -q --no-views --photos -o " + (dir / "out").string());
  ASSERT_EQ(run.code, 0) << run.out;
  std::ifstream poses(dir / "out/photos/poses.csv");
  std::string line;
  std::size_t rows = 0;
  while (std::getline(poses, line)) ++rows;
  ASSERT_GT(rows, 1U);
  std::size_t images = 0;
  for (const auto& e : fs::directory_iterator(dir / "out/photos/images")) {
    images += e.path().extension() == ".png" ? 1 : 0;
  }
  EXPECT_EQ(images, rows - 1);
  const auto bad = uavip::cli_test::uavip(
      "photos " + (dir / "out/mission.json").string() + " --world " + UAVIP_SOURCE_DIR +
      "/scenarios/single_cube.yaml -o " + (dir / "bad").string());
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_EQ(std::count(bad.out.begin(), bad.out.end(), '\n'), 1) << bad.out;
  EXPECT_FALSE(fs::exists(dir / "bad/photos.json"));
  fs::remove_all(dir);
}

/// The world's rectangles as a triangle mesh, two triangles a rectangle.
io::TriangleMesh meshOf(const sim::WorldModel& w) {
  io::TriangleMesh mesh;
  for (const auto& r : w.rects()) {
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    for (const Vec3& c : {r.corner, Vec3(r.corner + r.edge_u), Vec3(r.corner + r.edge_u + r.edge_v),
                          Vec3(r.corner + r.edge_v)})
      mesh.vertices.push_back(c);
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
  }
  return mesh;
}

/// Brute force: the nearest triangle a ray meets (Möller–Trumbore in double; t = inf
/// when none).
double bruteForceTriangleHit(const io::TriangleMesh& mesh, const Vec3& o, const Vec3& d) {
  double best = kInf;
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const Vec3 e1 = b - a, e2 = c - a, p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-14) continue;
    const Vec3 s = o - a;
    const double u = s.dot(p) / det;
    const Vec3 q = s.cross(e1);
    const double v = d.dot(q) / det, dist = e2.dot(q) / det;
    if (u < -1e-9 || v < -1e-9 || u + v > 1 + 1e-9 || !(dist > 1e-9)) continue;
    best = std::min(best, dist);
  }
  return best;
}

TEST(RayCaster, MeshRaysHitWhatBruteForceFinds) {
  // A twisted soup: the tower world's triangles, every vertex moved by up to 5 cm.
  io::TriangleMesh mesh = meshOf(towerWorld());
  std::mt19937 jitter(5);
  std::uniform_real_distribution<double> small(-0.05, 0.05);
  for (Vec3& v : mesh.vertices) v += Vec3(small(jitter), small(jitter), small(jitter));
  mesh.triangles.push_back({0, 0, 1});  // degenerate: left out
  const photo::RayCaster caster(mesh, "soup.stl");
  EXPECT_EQ(caster.faces(), mesh.triangles.size() - 1);
  const auto k = smallCamera();
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> ux(0.0, k.width_px), uy(0.0, k.height_px);
  int hits = 0;
  for (const auto& view : towerViews()) {
    const PhotoPose pose = photo::poseFromView(view);
    for (int i = 0; i < 200; ++i) {
      const Vec3 d = photo::pixelRay(k, pose, ux(rng), uy(rng));
      const double t = bruteForceTriangleHit(mesh, pose.position, d);
      const photo::RayHit hit = caster.cast(pose.position, d);
      ASSERT_EQ(hit.hit, std::isfinite(t));
      if (!hit.hit) continue;
      ++hits;
      EXPECT_NEAR(hit.t, t, 1e-4);
      const auto& tri = mesh.triangles[hit.face];
      EXPECT_NEAR(hit.normal.dot(hit.point - mesh.vertices[tri[0]]), 0.0, 1e-9);
    }
  }
  EXPECT_GT(hits, 500);
}

TEST(RayCaster, MeshWithoutAreaIsRefused) {
  io::TriangleMesh flat;
  flat.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  flat.triangles = {{0, 1, 2}};
  try {
    const photo::RayCaster caster(flat, "line.stl");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line.stl"), std::string::npos) << e.what();
  }
}

TEST(Renderer, TheWorldAsTrianglesRendersAsItsRectangles) {
  const sim::WorldModel world = towerWorld();
  const photo::RayCaster rects(world), triangles(meshOf(world), "tower.stl");
  const photo::SurfaceTexture texture(photo::TextureOptions{});
  const auto k = smallCamera();
  std::size_t pixels = 0, differ = 0, surface = 0;
  for (const auto& view : towerViews()) {
    const PhotoPose pose = photo::poseFromView(view);
    const photo::Image a = photo::renderPhoto(rects, texture, k, pose);
    const photo::Image b = photo::renderPhoto(triangles, texture, k, pose);
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    for (std::size_t i = 0; i < a.rgb.size(); i += 3) {
      ++pixels;
      int diff = 0;
      for (std::size_t c = 0; c < 3; ++c)
        diff = std::max(diff, std::abs(a.rgb[i + c] - b.rgb[i + c]));
      differ += diff > 1 ? 1 : 0;
      surface += a.rgb[i] != photo::kSkyRgb[0] ? 1 : 0;
    }
  }
  EXPECT_GT(surface, pixels / 2);
  // Only pixels on a shared diagonal or a box edge may tie another way.
  EXPECT_LE(differ * 500, pixels) << differ << " of " << pixels;
}

TEST(PhotosCli, AgainstTheMeshAMissionWasDetectedFrom) {
  const fs::path dir = tempDir("mesh");
  fs::create_directories(dir);
  // A 2 x 1.5 m wall facing -y, 20 km east of the file's origin: detect recentres it.
  const auto writeWall = [&](const fs::path& file, double x0) {
    std::ofstream(file) << "v " << x0 << " 0 0.5\nv " << x0 + 2 << " 0 0.5\nv " << x0 + 2
                        << " 0 2\nv " << x0 << " 0 2\nf 1 2 3\nf 1 3 4\n";
  };
  writeWall(dir / "wall.obj", 20000.0);
  writeWall(dir / "moved.obj", 20010.0);
  std::ofstream(dir / "cfg.yaml")
      << "perception: {min_area_m2: 1.0}\n"
         "camera: {fx: 200, fy: 200, cx: 80, cy: 60, image_px: [160, 120], gsd_mm_per_px: 5}\n";
  const std::string d = (dir / "out").string(), cfg = (dir / "cfg.yaml").string();
  const auto det = uavip::cli_test::uavip("detect " + (dir / "wall.obj").string() + " -c " + cfg +
                                          " -q --no-views -o " + d);
  ASSERT_EQ(det.code, 0) << det.out;
  const auto plan = uavip::cli_test::uavip("plan " + d + "/scene.json --surface all -c " + cfg +
                                           " -q --no-views -o " + d);
  ASSERT_EQ(plan.code, 0) << plan.out;
  const auto photos = uavip::cli_test::uavip("photos " + d + "/mission.json --world " +
                                             (dir / "wall.obj").string() + " -o " + d + "/photos");
  ASSERT_EQ(photos.code, 0) << photos.out;
  EXPECT_NE(photos.out.find("targets on the world"), std::string::npos) << photos.out;
  std::ifstream poses(d + "/photos/poses.csv");
  std::string line;
  std::size_t rows = 0;
  while (std::getline(poses, line)) ++rows;
  ASSERT_GT(rows, 1U);
  std::size_t images = 0;
  for (const auto& e : fs::directory_iterator(d + "/photos/images")) {
    images += e.path().extension() == ".png" ? 1 : 0;
  }
  EXPECT_EQ(images, rows - 1);
  // A preview from the scene's own cloud (already recentred, read as it is).
  const auto own = uavip::cli_test::uavip("photos " + d + "/mission.json --world " + d +
                                          "/cloud_clean.pcd -q -o " + d + "/preview");
  EXPECT_EQ(own.code, 0) << own.out;
  // The same wall 10 m along: not the model the mission was planned on.
  const auto bad = uavip::cli_test::uavip("photos " + d + "/mission.json --world " +
                                          (dir / "moved.obj").string() + " -o " + d + "/bad");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_EQ(std::count(bad.out.begin(), bad.out.end(), '\n'), 1) << bad.out;
  EXPECT_FALSE(fs::exists(d + "/bad/photos.json"));
  fs::remove_all(dir);
}

TEST(PointPreview, SplatsLandWhereProjectionPredictsNearestFirst) {
  const auto k = smallCamera();
  const PhotoPose pose = photo::poseFromView(viewAt(Vec3(0, 0, 0), -Vec3::UnitY(), 2.0));
  photo::PreviewCloud cloud;
  // Two points on the optical axis (the far one first in the list), one off it.
  cloud.points = {Vec3(0.0, 1.0, 0.0), Vec3(0.0, 0.5, 0.0), Vec3(0.3, 0.0, 0.2)};
  cloud.rgb = {{{200, 0, 0}}, {{0, 200, 0}}, {{0, 0, 200}}};
  cloud.splat_m = 0.02;
  cloud.max_depth_m = 10.0;
  const photo::Image img = photo::renderPointPreview(cloud, k, pose);
  const auto at = [&](const Vec3& p) {
    const Eigen::Vector3d px = photo::projectToImage(k, pose, p);
    const std::size_t i = static_cast<std::size_t>(std::floor(px.y())) * img.width +
                          static_cast<std::size_t>(std::floor(px.x()));
    return std::array<int, 3>{img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]};
  };
  // The nearer green point (depth 1.5 m) hides the red one behind it (3 m).
  const auto centre = at(Vec3(0.0, 0.5, 0.0));
  EXPECT_EQ(centre[0], 0);
  EXPECT_GT(centre[1], 150);
  const auto off = at(Vec3(0.3, 0.0, 0.2));
  EXPECT_GT(off[2], 150);
  EXPECT_EQ(off[0], 0);
  // A pixel far from every splat is sky.
  EXPECT_EQ(img.rgb[0], photo::kSkyRgb[0]);
  // Beyond max_depth_m nothing is drawn.
  cloud.max_depth_m = 1.0;
  const photo::Image none = photo::renderPointPreview(cloud, k, pose);
  for (std::size_t i = 0; i < none.rgb.size(); i += 3) ASSERT_EQ(none.rgb[i], photo::kSkyRgb[0]);
}

TEST(PointPreview, ColoursOfAPcdInTheOrderOfItsPoints) {
  const fs::path dir = tempDir("colours");
  fs::create_directories(dir);
  // rgb packed in a float (PCL's convention), one point without a return (organized).
  const auto packed = [](std::uint32_t r, std::uint32_t g, std::uint32_t b) {
    const std::uint32_t v = (r << 16) | (g << 8) | b;
    float f;
    std::memcpy(&f, &v, 4);
    return f;
  };
  {
    std::ofstream pcd(dir / "c.pcd");
    pcd << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F F\n"
           "COUNT 1 1 1 1\nWIDTH 3\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 6\nDATA ascii\n";
    const std::uint32_t rgb[6][3] = {{255, 0, 0},  {0, 255, 0}, {0, 0, 255},
                                     {10, 20, 30}, {0, 0, 0},   {200, 100, 50}};
    for (int i = 0; i < 6; ++i) {
      pcd << (i == 4 ? std::string("nan nan nan") : std::to_string(i) + " 0 0") << " "
          << formatNumber(packed(rgb[i][0], rgb[i][1], rgb[i][2]), 12) << "\n";
    }
  }
  const PointList points = io::loadCloud((dir / "c.pcd").string());
  const io::PointColours c = io::loadCloudColours((dir / "c.pcd").string());
  ASSERT_EQ(points.size(), 5U);
  ASSERT_EQ(c.rgb.size(), points.size());
  EXPECT_EQ(c.source, "rgb");
  EXPECT_EQ(c.rgb[0], (std::array<std::uint8_t, 3>{255, 0, 0}));
  EXPECT_EQ(c.rgb[3], (std::array<std::uint8_t, 3>{10, 20, 30}));
  EXPECT_EQ(c.rgb[4], (std::array<std::uint8_t, 3>{200, 100, 50}));  // after the skipped one
  EXPECT_NEAR(points[4].x(), 5.0, 1e-9);
  // Intensity only: grey, stretched; x y z text: no colour.
  std::ofstream(dir / "i.pcd")
      << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n"
         "COUNT 1 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n"
         "0 0 0 100\n1 0 0 3000\n";
  const io::PointColours i = io::loadCloudColours((dir / "i.pcd").string());
  ASSERT_EQ(i.rgb.size(), 2U);
  EXPECT_EQ(i.rgb[0][0], 0);
  EXPECT_EQ(i.rgb[1][0], 255);
  std::ofstream(dir / "p.xyz") << "0 0 0\n1 1 1\n";
  EXPECT_TRUE(io::loadCloudColours((dir / "p.xyz").string()).rgb.empty());
  fs::remove_all(dir);
}

TEST(PhotosCli, PreviewFromTheCloudAMissionWasDetectedFrom) {
  const fs::path dir = tempDir("preview");
  fs::create_directories(dir);
  const fs::path scenario = writeSmallWall(dir);
  const std::string d = (dir / "out").string();
  const auto run = uavip::cli_test::uavip("run " + scenario.string() + " -q --no-views -o " + d);
  ASSERT_EQ(run.code, 0) << run.out;
  const auto preview = uavip::cli_test::uavip("photos " + d + "/mission.json --world " + d +
                                              "/cloud_clean.pcd -q -o " + d + "/preview");
  ASSERT_EQ(preview.code, 0) << preview.out;
  const std::string json = uavip::cli_test::slurp(d + "/preview/photos.json");
  EXPECT_NE(json.find("\"preview\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"height\""), std::string::npos) << json;  // a PCD without colour
  // Against the truth (the wall: x in [0, 2], z in [0.5, 2] on y = 0): pixels whose ray
  // meets the wall well inside show a point, pixels whose ray passes well clear show sky.
  const io::MissionRecord mission = io::loadMission(d + "/mission.json");
  const photo::PhotoCamera cam = photo::photoCamera(mission, d + "/mission.json");
  std::size_t images = 0, inside = 0, inside_drawn = 0, outside = 0, outside_sky = 0;
  for (const auto& p : photo::plannedPhotos(mission, cam, d + "/mission.json")) {
    int w = 0, h = 0;
    const auto rgb =
        decodePng(uavip::cli_test::slurp(d + "/preview/images/" + p.stop_id + ".png"), &w, &h);
    ASSERT_EQ(w, cam.intrinsics.width_px);
    for (int y = 0; y < h; y += 3) {
      for (int x = 0; x < w; x += 3) {
        const Vec3 ray = photo::pixelRay(cam.intrinsics, p.pose, x + 0.5, y + 0.5);
        const double t = std::abs(ray.y()) > 1e-9 ? -p.pose.position.y() / ray.y() : -1.0;
        const Vec3 hit = p.pose.position + t * ray;
        const bool in = t > 0 && hit.x() > 0.1 && hit.x() < 1.9 && hit.z() > 0.6 && hit.z() < 1.9;
        const bool out =
            t <= 0 || hit.x() < -0.2 || hit.x() > 2.2 || hit.z() < 0.3 || hit.z() > 2.2;
        const std::size_t c = 3 * (static_cast<std::size_t>(y) * w + static_cast<std::size_t>(x));
        const bool sky = rgb[c] == photo::kSkyRgb[0] && rgb[c + 1] == photo::kSkyRgb[1] &&
                         rgb[c + 2] == photo::kSkyRgb[2];
        inside += in ? 1 : 0;
        inside_drawn += in && !sky ? 1 : 0;
        outside += out ? 1 : 0;
        outside_sky += out && sky ? 1 : 0;
      }
    }
    ++images;
  }
  EXPECT_GT(inside, 1000U);
  EXPECT_GE(inside_drawn * 100, inside * 95) << inside_drawn << " of " << inside;
  EXPECT_GE(outside_sky * 1000, outside * 995) << outside_sky << " of " << outside;
  EXPECT_GT(images, 0U);
  // A cloud elsewhere: refused, nothing written.
  std::ofstream(dir / "far.xyz") << "50 50 50\n51 50 50\n50 51 50\n";
  const auto bad = uavip::cli_test::uavip("photos " + d + "/mission.json --world " +
                                          (dir / "far.xyz").string() + " -o " + d + "/bad");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_FALSE(fs::exists(d + "/bad/photos.json"));
  fs::remove_all(dir);
}

}  // namespace

namespace {

/// A structure's vertical edge (face A: x = 0, seen from −x; face B: y = 3, seen from
/// +y), each face's rows of photos and a column of photos along the edge at 45°, as
/// uavip's edge link flies it: 0.6 × 0.4 m footprints at 1.5 m.
struct EdgeScene {
  sim::WorldModel world;
  photo::PhotoCamera camera;
  std::vector<photo::PlannedPhoto> photos;
  std::vector<char> face;  ///< 'A', 'B' or 'e' (edge) per photo
};

EdgeScene edgeScene() {
  EdgeScene s;
  s.world.addPlane({"A", Vec3(0, 0, 0), Vec3(0, 3, 0), Vec3(0, 0, 2)});
  s.world.addPlane({"B", Vec3(0, 3, 0), Vec3(3, 0, 0), Vec3(0, 0, 2)});
  auto& k = s.camera.intrinsics;
  k.width_px = 600;
  k.height_px = 400;
  k.fx_px = k.fy_px = 1500.0;
  k.cx_px = 300.0;
  k.cy_px = 200.0;
  s.camera.standoff_m = 1.5;
  const auto add = [&](const Vec3& target, const Vec3& normal, char face) {
    photo::PlannedPhoto p;
    p.order = s.photos.size() + 1;
    p.stop_id = "p" + std::to_string(p.order);
    p.view = viewAt(target, normal, 1.5);
    p.pose = photo::poseFromView(p.view);
    p.target = target;
    p.footprint_w_m = 0.6;
    p.footprint_h_m = 0.4;
    s.photos.push_back(p);
    s.face.push_back(face);
  };
  for (const double z : {0.4, 0.75, 1.1, 1.45}) {
    for (double a = 0.1; a < 2.95; a += 0.19) {
      add(Vec3(0.0, a, z), -Vec3::UnitX(), 'A');
      add(Vec3(a, 3.0, z), Vec3::UnitY(), 'B');
    }
  }
  for (double z = 0.3; z < 1.75; z += 0.155)
    add(Vec3(0.0, 3.0, z), Vec3(-1.0, 1.0, 0.0).normalized(), 'e');
  return s;
}

/// Brute force: the share of the face points that photo a's rays through a 24 × 16
/// pixel grid hit first which photo b sees (in its image, ahead of it, in front of
/// the face: outward normals −x on A, +y on B).
double bruteForceOverlap(const EdgeScene& s, const photo::PlannedPhoto& a,
                         const photo::PlannedPhoto& b) {
  const auto& k = s.camera.intrinsics;
  int hits = 0, seen = 0;
  for (int iu = 0; iu < 24; ++iu) {
    for (int iv = 0; iv < 16; ++iv) {
      const double u = (iu + 0.5) * k.width_px / 24.0, v = (iv + 0.5) * k.height_px / 16.0;
      const Vec3 d =
          (a.pose.camera_to_world * Vec3((u - k.cx_px) / k.fx_px, (v - k.cy_px) / k.fy_px, 1.0))
              .normalized();
      Vec3 p;
      if (!std::isfinite(bruteForceHit(s.world, a.pose.position, d, &p))) continue;
      ++hits;
      const Vec3 n = std::abs(p.x()) < 1e-9 ? Vec3(-Vec3::UnitX()) : Vec3(Vec3::UnitY());
      const Vec3 c = b.pose.camera_to_world.transpose() * (p - b.pose.position);
      if (n.dot(b.pose.position - p) <= 0.0 || c.z() <= 0.0) continue;
      const double bu = k.fx_px * c.x() / c.z() + k.cx_px, bv = k.fy_px * c.y() / c.z() + k.cy_px;
      if (bu >= 0 && bu < k.width_px && bv >= 0 && bv < k.height_px) ++seen;
    }
  }
  return hits ? static_cast<double>(seen) / hits : 0.0;
}

}  // namespace

/// Every pair overlaps by brute force, every photo is paired with the photo that
/// overlaps it most, and every edge photo with photos of both faces (what COLMAP needs
/// to join the edge column to the faces). The camera centres' 10 nearest (COLMAP's
/// spatial matcher) miss the last: checked too, so the scene tells the rules apart.
/// seenShare: nothing from behind the face, beyond kPairMaxRayDeg or through a wall.
TEST(ViewPairs, PairPhotosThatSeeTheSamePointsEdgePhotosWithBothFaces) {
  const EdgeScene s = edgeScene();
  const std::size_t n = s.photos.size();
  std::vector<std::vector<double>> overlap(n, std::vector<double>(n, 0.0));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j)
      if (i != j) overlap[i][j] = bruteForceOverlap(s, s.photos[i], s.photos[j]);
  const photo::RayCaster surface(s.world);
  const auto pairs = photo::viewPairs(s.photos, s.camera, surface, photo::kPairsPerPhoto, 2);
  EXPECT_EQ(pairs, photo::viewPairs(s.photos, s.camera, surface, photo::kPairsPerPhoto, 1));
  std::vector<std::vector<std::size_t>> partners(n);
  for (const auto& [i, j] : pairs) {
    ASSERT_LT(i, j);
    EXPECT_GT(std::min(overlap[i][j], overlap[j][i]), 0.0) << "pair " << i << "-" << j;
    partners[i].push_back(j);
    partners[j].push_back(i);
  }
  int spatial_misses = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto best = static_cast<std::size_t>(
        std::max_element(overlap[i].begin(), overlap[i].end()) - overlap[i].begin());
    EXPECT_NE(std::find(partners[i].begin(), partners[i].end(), best), partners[i].end())
        << "photo " << i << " is not paired with " << best << " (overlap " << overlap[i][best]
        << ")";
    EXPECT_LE(partners[i].size(), n - 1);
    if (s.face[i] != 'e') continue;
    const auto sees = [&](const std::vector<std::size_t>& js, char f) {
      return std::any_of(js.begin(), js.end(), [&](std::size_t j) { return s.face[j] == f; });
    };
    EXPECT_TRUE(sees(partners[i], 'A') && sees(partners[i], 'B')) << "edge photo " << i;
    std::vector<std::size_t> near(n);
    std::iota(near.begin(), near.end(), std::size_t{0});
    const Vec3 c = s.photos[i].pose.position;
    std::sort(near.begin(), near.end(), [&](std::size_t a, std::size_t b) {
      return (s.photos[a].pose.position - c).norm() < (s.photos[b].pose.position - c).norm();
    });
    near.erase(near.begin());  // itself
    near.resize(10);
    spatial_misses += !(sees(near, 'A') && sees(near, 'B'));
  }
  EXPECT_GT(spatial_misses, 0) << "the 10 nearest centres pair every edge photo with both faces";
  // One photo of face A against cameras aimed at its target from other sides: behind
  // the face it sees nothing; beside it, within kPairMaxRayDeg of the photo's rays, it
  // shares; beyond that angle it does not (SIFT would not match); and a wall between
  // them hides what it would see.
  std::size_t mid = 0;  // the photo of face A aimed nearest (0, 1.5, 1)
  for (std::size_t i = 0; i < n; ++i)
    if (s.face[i] == 'A' && (s.photos[i].target - Vec3(0, 1.5, 1)).norm() <
                                (s.photos[mid].target - Vec3(0, 1.5, 1)).norm())
      mid = i;
  const photo::PlannedPhoto& a = s.photos[mid];
  const photo::PhotoSamples samples = photo::photoSamples(surface, s.camera.intrinsics, a.pose);
  ASSERT_FALSE(samples.points.empty());
  const auto cameraAt = [&](double deg, double side, const sim::WorldModel& w) {
    const Vec3 n(-std::cos(deg * kDegToRad), side * std::sin(deg * kDegToRad), 0.0);
    const photo::RayCaster caster(w);
    const photo::PhotoPose pose = photo::poseFromView(viewAt(a.target, n, 1.5));
    return photo::seenShare(caster, s.camera.intrinsics, samples, a.pose, pose);
  };
  EXPECT_GT(cameraAt(0.0, 1.0, s.world), 0.9);
  EXPECT_GT(cameraAt(0.8 * photo::kPairMaxRayDeg, 1.0, s.world), 0.0);
  EXPECT_EQ(cameraAt(1.3 * photo::kPairMaxRayDeg, 1.0, s.world), 0.0);
  EXPECT_EQ(cameraAt(180.0, 1.0, s.world), 0.0);  // behind face A
  sim::WorldModel walled = s.world;
  walled.addPlane({"screen", Vec3(-0.7, -1.0, -1.0), Vec3(0, 6, 0), Vec3(0, 0, 4)});
  EXPECT_EQ(cameraAt(0.0, 1.0, walled), 0.0);
  // pairs.txt names the images.
  const std::string text = photo::colmapPairs(s.photos, pairs);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), static_cast<std::ptrdiff_t>(pairs.size()));
  EXPECT_EQ(text.substr(0, text.find('\n')), s.photos[pairs[0].first].stop_id + ".png " +
                                                 s.photos[pairs[0].second].stop_id + ".png");
}
