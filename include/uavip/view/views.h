#pragma once
/// \file
/// Views that people open (docs/ARCHITECTURE.md, "CLI contract"; docs/formats.md, "Views"):
///  - OUT/scene.ply: ASCII PLY point cloud. Vertex properties x y z (float, ENU m),
///    red green blue (uchar; MeshLab and CloudCompare show them), kind (uchar: 0 =
///    point of no surface or obstacle, 1 = surface point, 2 = obstacle point, 3 =
///    photo stop) and surface (int: surface id of a surface point or stop, −1
///    otherwise; CloudCompare shows both as scalar fields). Colours: a surface's
///    points in surfaceColor(id), obstacle points kObstacleColor, other points
///    kCloudColor, stops kStopColor.
///  - OUT/path.obj: the flight as OBJ polylines (`v` vertices, one `l i j k …` line
///    per sortie, object `sortie_<k>`; without a flight one per surface, `surface_<id>`);
///    CloudCompare ignores PLY edges but draws OBJ lines, MeshLab draws both.
///  - OUT/overview.png: top, front and side views (equal scale, scale bar) of the
///    cloud, surface boundaries, photo footprints, stops and paths, with a legend
///    and a line per surface; drawn with the render module.
///  - OUT/mission.html: the mission in 3D in one self-contained page (view/mission_page.h).
/// Everything is deterministic for the same scene and missions.

#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/geodesy.h"
#include "uavip/planning/fleet_types.h"
#include "uavip/planning/types.h"
#include "uavip/render/figure.h"

namespace uavip::view {

/// Colour of surface `id` in every view (render::palette(id)).
render::Color surfaceColor(int id);
/// Points of obstacle clusters.
inline const render::Color kObstacleColor{0.30, 0.30, 0.30};
/// Cloud points that belong to no surface and no obstacle cluster.
inline const render::Color kCloudColor{0.78, 0.78, 0.78};
/// Photo stops in the PLY.
inline const render::Color kStopColor{0.86, 0.08, 0.24};

/// The coloured cloud and the stops as ASCII PLY text. Points: every surface's
/// inliers, then every obstacle's points, then the cloud points in neither.
std::string sceneToPly(const Scene& scene, const std::vector<planning::SurfaceMission>& missions);

/// The paths as OBJ text: with a flight (status ok) one polyline per sortie
/// (object `sortie_<k>`, home to home), else one per surface with waypoints.
std::string pathsToObj(const std::vector<planning::SurfaceMission>& missions,
                       const planning::FlightPlan* flight = nullptr);

/// Options of the overview picture.
struct OverviewOptions {
  std::string title{"uavip mission overview"};  ///< first line, e.g. the scenario name
  int width_px{1900};
  int height_px{1100};
  /// Cloud points drawn per view (evenly subsampled above this).
  std::size_t max_cloud_points{60000};
  /// The mission's required clearance [m], for mission.html's path colouring (NaN: 1 m).
  double clearance_m{std::numeric_limits<double>::quiet_NaN()};
  /// The scene's CRS for mission.html's picked points (MissionPageOptions::geo).
  std::optional<io::GeoFit> geo;
};

/// The overview figure (encode it with png() or svg()).
/// With a flight (status ok): every sortie in its colour, home, and each surface's
/// place in the order as a number where it is entered.
render::Figure overviewFigure(const Scene& scene,
                              const std::vector<planning::SurfaceMission>& missions,
                              const OverviewOptions& options = {},
                              const planning::FlightPlan* flight = nullptr);

/// The views as file contents.
struct ViewFiles {
  std::string ply;   ///< scene.ply
  std::string obj;   ///< path.obj
  std::string png;   ///< overview.png
  std::string html;  ///< mission.html, the 3D page (view/mission_page.h)
};

/// Renders the four views. Reads its arguments only, so it may run on a thread of
/// its own while the caller writes the scene and the mission.
/// With a fleet of several UAVs, mission.html draws each UAV's sorties in its colour and
/// replays the fleet's schedule (view/mission_page.h).
ViewFiles renderViews(const Scene& scene, const std::vector<planning::SurfaceMission>& missions,
                      const OverviewOptions& options = {},
                      const planning::FlightPlan* flight = nullptr,
                      const planning::FleetPlan* fleet = nullptr);

/// Stages rendered views as out_dir/scene.ply, path.obj, overview.png and mission.html.
void stageViews(io::StagedOutputs& outputs, const std::string& out_dir, const ViewFiles& views);

/// Stages out_dir/scene.ply, out_dir/path.obj, out_dir/overview.png and out_dir/mission.html in
/// `outputs` (io/atomic_file.h: written when the command commits its outputs). Throws InputError
/// naming a file that cannot be written.
void writeViews(io::StagedOutputs& outputs, const std::string& out_dir, const Scene& scene,
                const std::vector<planning::SurfaceMission>& missions,
                const OverviewOptions& options = {}, const planning::FlightPlan* flight = nullptr);

}  // namespace uavip::view
