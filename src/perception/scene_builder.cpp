#include "uavip/perception/scene_builder.h"

#include "uavip/core/stopwatch.h"

namespace uavip::perception {
void PerceptionOptions::validate(const std::string& where) const {
  planes.validate(where);
  clusters.validate(where);
}

const params::Table<PerceptionOptions>& PerceptionOptions::table() {
  static const params::Table<PerceptionOptions> t = [] {
    params::Table<PerceptionOptions> p;
    p.include("", &PerceptionOptions::planes, PlaneDetectionOptions::table());
    p.include("", &PerceptionOptions::clusters, ClusterOptions::table());
    return p;
  }();
  return t;
}

Scene buildScene(const PointList& clean, const PerceptionOptions& options, PerceptionStats* stats) {
  options.validate();
  Scene scene;

  auto start = SteadyClock::now();
  PlaneDetectionResult planes = detectPlanes(clean, options.planes);
  const double planes_seconds = secondsSince(start);

  start = SteadyClock::now();
  scene.obstacles = clusterObstacles(planes.remaining, options.clusters);
  const double clusters_seconds = secondsSince(start);

  scene.surfaces = std::move(planes.surfaces);
  scene.cloud = clean;
  if (stats != nullptr) {
    stats->planes = planes.stats;
    stats->planes_seconds = planes_seconds;
    stats->clusters_seconds = clusters_seconds;
  }
  return scene;
}

}  // namespace uavip::perception
