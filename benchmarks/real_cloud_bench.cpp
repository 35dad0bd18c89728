// Real clouds at default settings: stage times, what was found, peak memory.
//
//   uavip_real_cloud_bench CLOUD [CLOUD…] [--tile N] [--runs R]
//
// Each cloud (.pcd .ply .xyz .las) goes through what `uavip detect` and
// `uavip plan --surface <largest>` do with no config: measure, resolve the auto
// parameters, stages 3–5, then stages 6–7 for the largest surface with coverage.
// --tile N repeats the cloud on an N × N grid of copies side by side (a real
// cloud made into a large site, e.g. autzen's 359 × 172 m tiled 3 × 6 ≈ 1 km²):
// the memory bound of large sites is measured on real point patterns. Prints the
// median of R runs and the peak resident memory of the process.

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "bench_util.h"
#include "uavip/app/pipeline.h"
#include "uavip/core/geometry.h"
#include "uavip/core/stopwatch.h"
#include "uavip/io/cloud_io.h"

namespace {

/// nx × ny copies of the cloud, side by side along x and y (gap 1 m).
uavip::PointList tiled(const uavip::PointList& cloud, int nx, int ny) {
  if (nx == 1 && ny == 1) return cloud;
  const uavip::Aabb box = uavip::boundingBox(cloud);
  const uavip::Vec3 step = box.max - box.min + uavip::Vec3(1.0, 1.0, 0.0);
  uavip::PointList out;
  out.reserve(cloud.size() * static_cast<std::size_t>(nx * ny));
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      const uavip::Vec3 shift(i * step.x(), j * step.y(), 0.0);
      for (const auto& p : cloud) out.push_back(p + shift);
    }
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  uavip::bench_util::prepareProcess();
  std::vector<std::string> files;
  int tile_x = 1, tile_y = 1, runs = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--tile" && i + 2 < argc) {
      tile_x = std::atoi(argv[++i]);
      tile_y = std::atoi(argv[++i]);
    } else if (a == "--runs" && i + 1 < argc) {
      runs = std::max(1, std::atoi(argv[++i]));
    } else {
      files.push_back(a);
    }
  }
  if (files.empty() || tile_x < 1 || tile_y < 1) {
    std::fprintf(stderr,
                 "usage: uavip_real_cloud_bench CLOUD [CLOUD...] [--tile NX NY] [--runs R]\n");
    return 2;
  }
  std::printf(
      "| cloud | points | spacing m | extent m | voxel m | band m | tol m | grid m | surfaces | "
      "obstacles | "
      "largest m2 | stops | coverage %% | status | detect s | plan s | peak RSS MiB |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  try {
    for (const auto& file : files) {
      const uavip::PointList cloud = tiled(uavip::io::loadCloud(file), tile_x, tile_y);
      const uavip::app::Config config = uavip::app::parseConfig("", "(defaults)");
      std::vector<double> detect_s, plan_s;
      uavip::app::DetectResult d;
      uavip::app::PlanResult p;
      for (int r = 0; r < runs; ++r) {
        const auto t0 = uavip::SteadyClock::now();
        d = uavip::app::detect(cloud, config, uavip::app::measure(cloud));
        detect_s.push_back(uavip::secondsSince(t0));
        int largest = -1;
        double area = -1.0;
        for (const auto& s : d.scene.surfaces) {
          if (s.area_m2 > area) area = s.area_m2, largest = s.id;
        }
        const auto t1 = uavip::SteadyClock::now();
        if (largest >= 0) p = uavip::app::plan(d.scene, d.resolved.config, {largest});
        plan_s.push_back(uavip::secondsSince(t1));
      }
      const auto& c = *d.scene.measured;
      const auto& pc = d.resolved.config;
      const uavip::planning::SurfaceMission* m = p.missions.empty() ? nullptr : &p.missions.front();
      double largest_area = 0.0;
      for (const auto& s : d.scene.surfaces) largest_area = std::max(largest_area, s.area_m2);
      std::printf(
          "| %s%s | %zu | %.3f | %.0f × %.0f × %.0f | %.3f | %.3f | %.2f | %.3f | %zu | %zu | %.0f "
          "| %zu | %.1f | %s | "
          "%.2f | %.2f | %.0f |\n",
          file.substr(file.find_last_of('/') + 1).c_str(),
          tile_x * tile_y > 1 ? (" ×" + std::to_string(tile_x * tile_y)).c_str() : "", c.points,
          c.spacing_m, c.extent_m.x(), c.extent_m.y(), c.extent_m.z(), pc.preprocess.voxel_m,
          pc.perception.planes.distance_threshold_m, pc.perception.clusters.tolerance_m,
          p.grid_resolution_m, d.scene.surfaces.size(), d.scene.obstacles.size(), largest_area,
          m ? m->strategy.stops.size() : std::size_t{0},
          m && m->coverage.evaluated ? 100.0 * m->coverage.fraction : 0.0,
          m ? uavip::planning::toString(m->status) : "-", uavip::bench_util::median(detect_s),
          uavip::bench_util::median(plan_s), uavip::bench_util::peakRssMiB());
      std::fflush(stdout);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uavip_real_cloud_bench: %s\n", e.what());
    return 2;
  }
  return 0;
}
