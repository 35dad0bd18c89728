// uavip view: the 3D mission page (view/mission_page.h) for a mission.json and the
// scene.json beside it, found as `uavip validate` finds it.

#include <filesystem>
#include <iostream>
#include <memory>

#include "src/cli/commands.h"
#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/json_reader.h"
#include "uavip/io/scene_json.h"
#include "uavip/view/mission_page.h"

namespace uavip::cli {
namespace {

namespace fs = std::filesystem;

}  // namespace

std::optional<io::GeoFit> pageGeoFit(const std::optional<io::SceneCrsRecord>& crs,
                                     const Scene& scene, const Verbosity& v) {
  if (!crs || scene.cloud.empty()) return std::nullopt;
  try {
    const auto transform = std::make_shared<const io::CrsTransform>(crs->definition, "crs");
    const io::Georeference geo(transform, crs->source_offset_m,
                               io::defaultVerticalDatum(*transform, crs->vertical, "scene.json"));
    const Aabb box = boundingBox(scene.cloud);
    return io::fitGeoreference(geo, box.min, box.max);
  } catch (const InputError& e) {
    if (!v.quiet)
      std::cerr << "uavip: warning: mission.html shows local metres only: " << e.what() << "\n";
    return std::nullopt;
  }
}

namespace {

int viewCommand(const std::string& mission_path, std::string scene_path, std::string out,
                const Verbosity& v) {
  if (scene_path.empty())
    scene_path = (fs::path(mission_path).parent_path() / "scene.json").string();
  if (out.empty()) out = (fs::path(mission_path).parent_path() / "mission.html").string();
  const nlohmann::json mission = io::JsonReader(mission_path).load();
  if (!fs::exists(scene_path))
    throw InputError(
        mission_path + ": its scene " + scene_path +
        " does not exist; give the scene.json the mission was planned on with --scene");
  const nlohmann::json scene_json = io::JsonReader(scene_path).load();
  const Scene scene = io::sceneFromJson(scene_json, scene_path);
  io::requireDistinctOutputs({mission_path, scene_path}, {out});
  view::MissionPageOptions options;
  options.geo = pageGeoFit(io::sceneCrsFromJson(scene_json, scene_path), scene, v);
  options.title = fs::path(mission_path).parent_path().filename().string();
  options.title = (options.title.empty() ? std::string() : options.title + ": ") + "uavip mission";
  const std::string page = view::missionPage(scene, &mission, options, mission_path);
  io::writeFileAtomic(out, page);
  if (!v.quiet)
    std::cout << "view: " << out << " ("
              << (page.size() + std::size_t{512} * 1024) / (std::size_t{1024} * 1024) << " MB)\n";
  return kExitOk;
}

/// Options of view, kept alive until dispatch.
struct ViewArgs {
  std::string mission, scene, out;
};

}  // namespace

void addViewCommands(CLI::App& cli, CommandRegistry& registry) {
  const auto [view, a] = missionCommand<ViewArgs>(
      cli, "view",
      "Write the mission as one self-contained 3D page (HTML, opens offline in any browser)");
  const Verbosity& v = registry.verbosity();
  view->add_option("--scene", a->scene, "Its scene (default: scene.json next to the mission)");
  view->add_option("-o,--out", a->out, "Page to write (default: mission.html next to the mission)");
  registry.add(view, [a = a, &v] { return viewCommand(a->mission, a->scene, a->out, v); });
}

}  // namespace uavip::cli
