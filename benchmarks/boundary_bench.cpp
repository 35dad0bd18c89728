// Boundaries that follow the surface against the paper's convex hull, on
// the concave walls of scenarios/ (L, U, window): photo stops whose view ray meets no
// true rectangle, coverage of the true wall by the footprints, the boundary's area
// against the truth (app/boundary_truth.h), and the time of detect + plan (stages 3-7).
// Usage: uavip_boundary_bench [SCENARIO.yaml ...]
//        (default scenarios/wall_l.yaml, wall_u.yaml, wall_window.yaml)
// Numbers go in benchmarks/README.md, never in tests.

#include <cstdio>
#include <string>
#include <vector>

#include "bench_util.h"
#include "uavip/app/boundary_truth.h"
#include "uavip/app/pipeline.h"
#include "uavip/app/scenario.h"
#include "uavip/core/stopwatch.h"

int main(int argc, char** argv) {
  uavip::bench_util::prepareProcess();
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) files.emplace_back(argv[i]);
  if (files.empty()) {
    for (const char* f : {"wall_l.yaml", "wall_u.yaml", "wall_window.yaml"})
      files.push_back(std::string(UAVIP_SOURCE_DIR) + "/scenarios/" + f);
  }
  std::printf(
      "| wall | boundary | vertices / holes | photo stops | over air | coverage | area (truth) | "
      "area error | detect + plan |\n|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& file : files) {
    for (const char* kind : {"convex", "outline"}) {
      uavip::app::Scenario sc = uavip::app::loadScenario(file);
      sc.config.perception.planes.boundary = kind;
      const auto raw = uavip::app::sense(sc);
      const auto t0 = uavip::SteadyClock::now();
      const auto d = uavip::app::detect(raw, sc.config, uavip::app::measure(raw, &sc));
      if (d.scene.surfaces.empty()) {
        std::printf("| %s | %s | no surface |\n", sc.name.c_str(), kind);
        continue;
      }
      const auto& s = d.scene.surfaces[0];
      const auto p = uavip::app::plan(d.scene, d.resolved.config, {s.id});
      const double seconds = uavip::secondsSince(t0);
      const auto score = uavip::app::scoreBoundary(s, p.missions[0].strategy, sc.world.rects());
      std::printf(
          "| %s | %s | %zu / %zu | %zu | %zu | %.2f %% | %.2f (%.2f) m² | %.2f %% | %.2f s |\n",
          sc.name.c_str(), kind, s.boundary.size(), s.holes.size(), score.stops,
          score.stops_over_air, 100.0 * score.coverage, score.area_m2, score.truth_area_m2,
          100.0 * score.area_error, seconds);
    }
  }
  return 0;
}
