// uavip photos: every photo stop of a mission rendered against the simulator's ground
// truth or a mesh of the structure, with the COLMAP model and poses beside them
// (photo/photo_folder.h).

#include <cctype>
#include <filesystem>
#include <iostream>
#include <memory>

#include "src/cli/commands.h"
#include "uavip/app/scenario.h"
#include "uavip/core/parallel.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/cloud_io.h"
#include "uavip/io/json_reader.h"
#include "uavip/io/mesh_reader.h"
#include "uavip/photo/photo_folder.h"

namespace uavip::cli {

namespace {

/// The options of a render: threads and the progress line about every 5 %.
photo::PhotoOptions photoOptions(int threads, double image_scale, const Verbosity& v) {
  photo::PhotoOptions options;
  options.threads = threads > 0 ? threads : hardwareThreads();
  options.image_scale = image_scale;
  if (v.showProgress()) {
    // About every 5 %: a line per batch would flood the terminal on long runs.
    options.progress = [last = std::size_t{0}](std::size_t done, std::size_t total) mutable {
      const std::size_t step = done * 20 / total;
      if (step == last && done < total) return;
      last = step;
      std::cerr << "uavip: photos " << done << "/" << total << "\n";
    };
  }
  return options;
}

/// The summary lines of a render.
void printSummary(const photo::PhotoSummary& s, const std::string& out, const Verbosity& v) {
  if (!v.quiet) {
    std::cout << "photos: " << s.photos << " in " << out << "/images ("
              << formatFixed(s.megapixels, 1) << " MP, " << formatFixed(s.seconds, 2) << " s, "
              << formatFixed(s.seconds / std::max(s.megapixels, 1e-9), 3)
              << " s/MP); COLMAP model in " << out << "/sparse, poses.csv, photos.json\n"
              << "photos: targets on the world: " << (s.match.targets - s.match.far) << " of "
              << s.match.targets << " within " << formatNumber(s.match.tolerance_m, 3)
              << " m (median " << formatNumber(s.match.median_m, 3) << " m)\n";
  }
}

/// scene.json's document, or an empty one when there is none (the file's own frame).
nlohmann::json sceneDocument(const std::string& scene_path) {
  if (!std::filesystem::exists(scene_path)) return nlohmann::json::object();
  return io::JsonReader(scene_path).load();
}

/// A mesh in the mission's frame (readInSceneFrame: as detect read its input).
TriangleMesh meshInMissionFrame(const std::string& mesh_path, const std::string& scene_path) {
  SceneFrameInput read = readInSceneFrame(mesh_path, sceneDocument(scene_path), scene_path);
  if (!read.triangles) throw InputError(mesh_path + ": not read as a mesh");
  return *read.triangles;
}

/// A cloud in the mission's frame (readInSceneFrame), with its colours.
photo::PreviewCloud cloudInMissionFrame(const std::string& cloud_path,
                                        const std::string& scene_path, std::string& colour_source) {
  photo::PreviewCloud cloud;
  cloud.points = readInSceneFrame(cloud_path, sceneDocument(scene_path), scene_path).points;
  io::PointColours colours = io::loadCloudColours(cloud_path);
  if (colours.rgb.size() == cloud.points.size()) {
    cloud.rgb = std::move(colours.rgb);
    colour_source = colours.source;
  }
  return cloud;
}

}  // namespace

int renderPlanPhotos(const std::string& mission_path, const sim::WorldModel& world,
                     const std::string& world_path, const std::string& out, int threads,
                     double image_scale, const Verbosity& v) {
  const io::MissionRecord mission = io::loadMission(mission_path);
  io::requireDistinctOutputs({mission_path, world_path}, {out + "/photos.json"});
  printSummary(photo::writePhotoFolder(mission, mission_path, world, world_path, out,
                                       photoOptions(threads, image_scale, v)),
               out, v);
  return kExitOk;
}

namespace {

/// `uavip photos` against a mesh (photo::writePhotoFolder's mesh form).
int renderMeshPhotos(const std::string& mission_path, const std::string& mesh_path,
                     std::string scene_path, const std::string& out, int threads,
                     double image_scale, const Verbosity& v) {
  const io::MissionRecord mission = io::loadMission(mission_path);
  if (scene_path.empty())
    scene_path = (std::filesystem::path(mission_path).parent_path() / "scene.json").string();
  io::requireDistinctOutputs({mission_path, mesh_path}, {out + "/photos.json"});
  const TriangleMesh mesh = meshInMissionFrame(mesh_path, scene_path);
  printSummary(photo::writePhotoFolder(mission, mission_path, mesh, mesh_path, out,
                                       photoOptions(threads, image_scale, v)),
               out, v);
  return kExitOk;
}

/// `uavip photos` previewed from a measured cloud (photo::writePreviewFolder): splats
/// 2 x the cloud's median spacing wide unless `splat_m` > 0, points up to
/// `max_depth_m` (0: 4 x the standoff, at least 10 m).
int renderCloudPreview(const std::string& mission_path, const std::string& cloud_path,
                       std::string scene_path, double splat_m, double max_depth_m,
                       const std::string& out, int threads, double image_scale,
                       const Verbosity& v) {
  const io::MissionRecord mission = io::loadMission(mission_path);
  if (scene_path.empty())
    scene_path = (std::filesystem::path(mission_path).parent_path() / "scene.json").string();
  io::requireDistinctOutputs({mission_path, cloud_path}, {out + "/photos.json"});
  std::string colour_source;
  photo::PreviewCloud cloud = cloudInMissionFrame(cloud_path, scene_path, colour_source);
  cloud.splat_m = splat_m > 0.0 ? splat_m : 2.0 * photo::medianSpacing(cloud.points);
  if (!(cloud.splat_m > 0.0)) cloud.splat_m = 0.01;  // every point in one place
  const double standoff = photo::photoCamera(mission, mission_path, image_scale).standoff_m;
  cloud.max_depth_m = max_depth_m > 0.0 ? max_depth_m : std::max(10.0, 4.0 * standoff);
  if (v.showProgress())
    std::cerr << "uavip: preview from " << cloud.points.size() << " points ("
              << (colour_source.empty() ? std::string("height ramp") : colour_source)
              << "), splats " << formatNumber(cloud.splat_m, 3) << " m, up to "
              << formatNumber(cloud.max_depth_m, 3) << " m\n";
  printSummary(photo::writePreviewFolder(mission, mission_path, cloud, cloud_path, colour_source,
                                         out, photoOptions(threads, image_scale, v)),
               out, v);
  return kExitOk;
}

/// True for a scenario file (.yaml, .yml): --world is then the simulator's world.
bool isScenarioFile(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".yaml" || ext == ".yml";
}

/// Options of photos, kept alive until dispatch.
struct PhotoArgs {
  std::string mission, world, scene, out;
  int threads{0};
  double splat_m{0.0}, max_depth_m{0.0}, image_scale{1.0};
};

}  // namespace

void addPhotoCommands(CLI::App& cli, CommandRegistry& registry) {
  const auto [photos, a] = missionCommand<PhotoArgs>(
      cli, "photos",
      "Render every photo stop of the flight against a scenario's ground-truth world or a "
      "mesh of the structure (PNG per stop, COLMAP text model, poses.csv)");
  const Verbosity& v = registry.verbosity();
  photos
      ->add_option("--world", a->world,
                   "Scenario YAML whose world the mission was planned on; a mesh of the "
                   "structure (.stl, .obj, .ply with faces, .gltf, .glb, ...) in the coordinates "
                   "of the input detect read; or a cloud (.pcd, .ply, .las, .xyz): a preview "
                   "drawn from its points")
      ->required();
  photos->add_option("--scene", a->scene,
                     "A mesh's or cloud's frame: the scene.json whose input.scale and "
                     "source_offset_m apply (default: beside the mission)");
  photos->add_option("--splat", a->splat_m,
                     "Cloud preview: a point's drawn width [m] (default 2 x the median spacing)");
  photos->add_option("--max-depth", a->max_depth_m,
                     "Cloud preview: points farther from the camera are not drawn [m] (default 4 x "
                     "the standoff, at least 10)");
  photos->add_option("-o,--out", a->out, "Output folder (images/, sparse/, poses.csv, photos.json)")
      ->required();
  photos->add_option("--threads", a->threads, "Worker threads (default: every core)");
  photos->add_option("--image-scale", a->image_scale,
                     "Render the same views with the image size and focal lengths x this, in "
                     "(0, 1]: a quicker, coarser check (the texture follows the coarser GSD)");
  registry.add(photos, [a = a, &v] {
    if (io::isMeshFile(a->world))
      return renderMeshPhotos(a->mission, a->world, a->scene, a->out, a->threads, a->image_scale,
                              v);
    if (!isScenarioFile(a->world))
      return renderCloudPreview(a->mission, a->world, a->scene, a->splat_m, a->max_depth_m, a->out,
                                a->threads, a->image_scale, v);
    const app::Scenario scenario = app::loadScenario(a->world);
    return renderPlanPhotos(a->mission, scenario.world, a->world, a->out, a->threads,
                            a->image_scale, v);
  });
}

}  // namespace uavip::cli
