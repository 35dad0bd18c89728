// uavip photos: every photo stop of a mission rendered against the simulator's ground
// truth or a mesh of the structure, with the COLMAP model and poses beside them
// (photo/photo_folder.h).

#include <filesystem>
#include <iostream>
#include <memory>

#include "src/cli/commands.h"
#include "uavip/app/scenario.h"
#include "uavip/core/parallel.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/json_reader.h"
#include "uavip/io/mesh_reader.h"
#include "uavip/photo/photo_folder.h"

namespace uavip::cli {

namespace {

/// The options of a render: threads and the progress line about every 5 %.
photo::PhotoOptions photoOptions(int threads, const Verbosity& v) {
  photo::PhotoOptions options;
  options.threads = threads > 0 ? threads : hardwareThreads();
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

/// A mesh in the mission's frame: the file's coordinates times input.scale, less
/// source_offset_m, as scene.json records them for the input detect read (the same
/// file, or a mesh of it in the same coordinates). No scene.json: the file's own frame.
io::TriangleMesh meshInMissionFrame(const std::string& mesh_path, const std::string& scene_path) {
  double scale = 1.0;
  Vec3 offset = Vec3::Zero();
  if (std::filesystem::exists(scene_path)) {
    const io::JsonReader reader(scene_path);
    const nlohmann::json j = reader.load();
    if (j.contains("input_read") && j.at("input_read").contains("scale"))
      scale = reader.number(j.at("input_read").at("scale"), "input_read.scale");
    if (j.contains("source_offset_m"))
      offset = reader.vec3(j.at("source_offset_m"), "source_offset_m", false);
  }
  io::TriangleMesh mesh = io::readMesh(mesh_path, scale);
  for (Vec3& p : mesh.vertices) p -= offset;
  return mesh;
}

}  // namespace

int renderPlanPhotos(const std::string& mission_path, const sim::WorldModel& world,
                     const std::string& world_path, const std::string& out, int threads,
                     const Verbosity& v) {
  const io::MissionRecord mission = io::loadMission(mission_path);
  io::requireDistinctOutputs({mission_path, world_path}, {out + "/photos.json"});
  printSummary(photo::writePhotoFolder(mission, mission_path, world, world_path, out,
                                       photoOptions(threads, v)),
               out, v);
  return kExitOk;
}

namespace {

/// `uavip photos` against a mesh (photo::writePhotoFolder's mesh form).
int renderMeshPhotos(const std::string& mission_path, const std::string& mesh_path,
                     std::string scene_path, const std::string& out, int threads,
                     const Verbosity& v) {
  const io::MissionRecord mission = io::loadMission(mission_path);
  if (scene_path.empty())
    scene_path = (std::filesystem::path(mission_path).parent_path() / "scene.json").string();
  io::requireDistinctOutputs({mission_path, mesh_path}, {out + "/photos.json"});
  const io::TriangleMesh mesh = meshInMissionFrame(mesh_path, scene_path);
  printSummary(photo::writePhotoFolder(mission, mission_path, mesh, mesh_path, out,
                                       photoOptions(threads, v)),
               out, v);
  return kExitOk;
}

/// Options of photos, kept alive until dispatch.
struct PhotoArgs {
  std::string mission, world, scene, out;
  int threads{0};
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
                   "Scenario YAML whose world the mission was planned on, or a mesh of the "
                   "structure (.stl, .obj, .ply with faces, .gltf, .glb, ...) in the coordinates "
                   "of the input detect read")
      ->required();
  photos->add_option("--scene", a->scene,
                     "A mesh's frame: the scene.json whose input.scale and source_offset_m "
                     "apply (default: beside the mission)");
  photos->add_option("-o,--out", a->out, "Output folder (images/, sparse/, poses.csv, photos.json)")
      ->required();
  photos->add_option("--threads", a->threads, "Worker threads (default: every core)");
  registry.add(photos, [a = a, &v] {
    if (io::isMeshFile(a->world))
      return renderMeshPhotos(a->mission, a->world, a->scene, a->out, a->threads, v);
    const app::Scenario scenario = app::loadScenario(a->world);
    return renderPlanPhotos(a->mission, scenario.world, a->world, a->out, a->threads, v);
  });
}

}  // namespace uavip::cli
