// Writes the large clouds of the tiling benchmark (benchmarks/tile_scale.sh) as x y z
// text, span by span, so that no more than one span is ever in memory:
//
//   uavip_site_cloud --viaduct KM -o viaduct.xyz [--spacing M]
//       the bridge of scenarios/bridge_sampled.yaml (deck 22 x 10 m, a two-column pier,
//       trees and grass) repeated every 22 m along x for KM kilometres: the deck is one
//       continuous 0.9 m deep slab, a pier every 22 m, the abutment at the start only,
//       the ground one 22 x 24 m strip per span; each span sampled with its own seed.
//   uavip_site_cloud --repeat CLOUD NX NY -o site.xyz
//       a real cloud repeated on an NX x NY grid side by side (autzen_trim.las 3 x 6 is
//       the 1 km² airborne site of benchmarks/README.md).

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

#include "uavip/app/scenario.h"
#include "uavip/core/error.h"
#include "uavip/io/cloud_io.h"
#include "uavip/sim/surface_sampler.h"

namespace {

constexpr double kSpanM = 22.0;  // the bridge piece of bridge_sampled.yaml

void write(std::ofstream& out, const uavip::PointList& points) {
  char line[96];
  for (const uavip::Vec3& p : points) {
    const int n = std::snprintf(line, sizeof line, "%.4f %.4f %.4f\n", p.x(), p.y(), p.z());
    out.write(line, n);
  }
}

int viaduct(double km, double spacing, const std::string& path) {
  const uavip::app::Scenario bridge =
      uavip::app::loadScenario(std::string(UAVIP_SOURCE_DIR) + "/scenarios/bridge_sampled.yaml");
  const long spans = std::lround(std::ceil(km * 1000.0 / kSpanM));
  std::ofstream out(path);
  std::size_t total = 0;
  for (long k = 0; k < spans; ++k) {
    uavip::sim::WorldModel span;
    const uavip::Vec3 shift(kSpanM * static_cast<double>(k), 0.0, 0.0);
    for (uavip::sim::Rect r : bridge.world.rects()) {
      if (r.name == "ground") continue;                         // one strip per span below
      if (r.name.rfind("abutment", 0) == 0 && k > 0) continue;  // at the start only
      r.corner += shift;
      span.addPlane(r);
    }
    span.addPlane({"ground", uavip::Vec3(kSpanM * static_cast<double>(k), -7.0, 0.0),
                   uavip::Vec3(kSpanM, 0.0, 0.0), uavip::Vec3(0.0, 24.0, 0.0)});
    uavip::sim::SampleOptions so = bridge.sample;
    so.spacing_m = spacing;
    so.seed = bridge.sample.seed + static_cast<std::uint32_t>(k);
    const uavip::PointList points = uavip::sim::sampleSurfaces(span, so);
    write(out, points);
    total += points.size();
  }
  std::cout << path << ": viaduct of " << spans << " spans ("
            << kSpanM * static_cast<double>(spans) / 1000.0 << " km), " << total << " points\n";
  return out ? 0 : 1;
}

int repeat(const std::string& cloud, int nx, int ny, const std::string& path) {
  const uavip::PointList points = uavip::io::loadCloud(cloud);
  uavip::Vec3 lo = points.front(), hi = points.front();
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const uavip::Vec3 size = hi - lo;
  std::ofstream out(path);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      uavip::PointList copy = points;
      for (auto& p : copy) p += uavip::Vec3(i * size.x(), j * size.y(), 0.0);
      write(out, copy);
    }
  }
  std::cout << path << ": " << cloud << " repeated " << nx << " x " << ny << ", "
            << points.size() * static_cast<std::size_t>(nx * ny) << " points\n";
  return out ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string mode = argc > 1 ? argv[1] : "";
    std::string out;
    double spacing = 0.1;
    for (int i = 1; i + 1 < argc; ++i) {
      if (std::string(argv[i]) == "-o") out = argv[i + 1];
      if (std::string(argv[i]) == "--spacing") spacing = std::atof(argv[i + 1]);
    }
    if (mode == "--viaduct" && argc > 2 && !out.empty())
      return viaduct(std::atof(argv[2]), spacing, out);
    if (mode == "--repeat" && argc > 4 && !out.empty())
      return repeat(argv[2], std::atoi(argv[3]), std::atoi(argv[4]), out);
    std::cerr << "usage: uavip_site_cloud --viaduct KM -o FILE.xyz [--spacing M]\n"
                 "       uavip_site_cloud --repeat CLOUD NX NY -o FILE.xyz\n";
    return 2;
  } catch (const uavip::InputError& e) {
    std::cerr << "uavip_site_cloud: error: " << e.what() << "\n";
    return 2;
  }
}
