#pragma once
/// The small site the tiling tests share: a 40 x 4 x 3 m block on a 50 x 14 m ground,
/// sampled every 0.1 m (noise 5 mm, seed 5); four 15 m tiles along x, one row.

#include <filesystem>
#include <fstream>
#include <string>

#include "uavip/core/types.h"
#include "uavip/sim/surface_sampler.h"
#include "uavip/sim/world_model.h"

namespace uavip::test {

/// Samples the block site and writes it as XYZ text to `xyz_path`; returns the points.
inline PointList writeBlockSite(const std::filesystem::path& xyz_path) {
  sim::WorldModel w;
  w.addBox("block", Vec3(5.0, 5.0, 0.0), Vec3(45.0, 9.0, 3.0));
  w.addPlane({"ground", Vec3(0.0, 0.0, 0.0), Vec3(50.0, 0.0, 0.0), Vec3(0.0, 14.0, 0.0)});
  sim::SampleOptions so;
  so.spacing_m = 0.1;
  so.noise_sigma_m = 0.005;
  so.seed = 5;
  PointList points = sim::sampleSurfaces(w, so);
  std::ofstream out(xyz_path);
  out.precision(10);
  for (const Vec3& p : points) out << p.x() << " " << p.y() << " " << p.z() << "\n";
  return points;
}

}  // namespace uavip::test
