#pragma once
/// \file
/// Shared pieces of the uavip command line. Each group of subcommands lives in its
/// own file and registers itself with a CommandRegistry; main.cpp parses and
/// dispatches. Exit codes: 0 done (a blocked surface is a result), 2 bad input or
/// usage, 3 no collision-free mission for the chosen surface.

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uavip/app/pipeline.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/geodesy.h"
#include "uavip/io/mission_json.h"
#include "uavip/io/scene_json.h"

namespace uavip::cli {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;
constexpr int kExitNoMission = 3;

/// How much goes to stderr.
struct Verbosity {
  bool quiet{false};
  bool verbose{false};
  /// Progress is shown on a terminal, or always with --verbose, never with --quiet.
  bool showProgress() const;
};

/// A progress callback printing "uavip: <msg>" on stderr when verbosity allows.
app::Progress progressPrinter(const Verbosity& v);

/// Subcommands and the action each runs once it was chosen.
class CommandRegistry {
 public:
  explicit CommandRegistry(const Verbosity& verbosity) : verbosity_(verbosity) {}
  /// Registers `action` for `sub`; it returns the process exit code.
  void add(CLI::App* sub, std::function<int()> action) {
    commands_.emplace_back(sub, std::move(action));
  }
  const Verbosity& verbosity() const { return verbosity_; }
  /// Runs the parsed subcommand's action (kExitBadInput if none was parsed).
  int dispatch() const;

 private:
  const Verbosity& verbosity_;
  std::vector<std::pair<CLI::App*, std::function<int()>>> commands_;
};

/// Subcommand `name` of cli that reads a mission: its required first argument
/// "mission" (OUT/mission.json written by run or plan) is stored in `mission`.
CLI::App* addMissionCommand(CLI::App& cli, const std::string& name, const std::string& description,
                            std::string& mission);

/// addMissionCommand with the subcommand's options, `Args` (which has a `mission`
/// string), made here and shared with its action so that they live until dispatch.
template <typename Args>
std::pair<CLI::App*, std::shared_ptr<Args>> missionCommand(CLI::App& cli, const std::string& name,
                                                           const std::string& description) {
  auto args = std::make_shared<Args>();
  return {addMissionCommand(cli, name, description, args->mission), args};
}

/// The scene's CRS in closed form for mission.html (io::fitGeoreference over the
/// cloud's box), or none: no CRS, or one PROJ cannot use (a warning says so; the page
/// is a convenience, the exports check the CRS themselves). view_commands.cpp.
std::optional<io::GeoFit> pageGeoFit(const std::optional<io::SceneCrsRecord>& crs,
                                     const Scene& scene, const Verbosity& v);

/// The CRS scene.json records: --crs for a cloud that does not state one (a
/// contradiction of the file's is a warning naming both), the vertical datum from
/// --vertical, else from a compound CRS's vertical part (EGM96 / EGM2008 height)
/// (pipeline_commands.cpp; detect, tile).
void resolveCrs(io::CloudReadInfo& read, const std::string& cloud_path, const std::string& crs,
                const std::string& vertical, const Verbosity& v);

/// An input file read as `detect` read it, in the scene's frame.
struct SceneFrameInput {
  PointList points;  ///< [m]; a mesh's points sampled at detect's spacing
  std::shared_ptr<const TriangleMesh> triangles;  ///< a mesh's triangles with area; null: a cloud
};

/// Reads `path` with scene.json's input_read (scale, drop_classes, a mesh's sampling
/// spacing) and moves it into the scene's frame (source_offset_m); `j` is scene.json's
/// document (`scene_path` names it in messages; an empty object: the file's own frame).
/// The clouds detect wrote beside scene.json (cloud_clean.pcd, cloud_safety.pcd) are read
/// as they are: they are in the scene's frame already.
/// validate_commands.cpp; used by validate and photos.
SceneFrameInput readInSceneFrame(const std::string& path, const nlohmann::json& j,
                                 const std::string& scene_path);

/// Stages scene.json and the clean and safety clouds beside it in `out` (`read`: how
/// a cloud file was read; null for a scenario) (pipeline_commands.cpp).
void writeScene(io::StagedOutputs& outputs, const std::string& out, const app::DetectResult& d,
                const io::CloudReadInfo* read = nullptr);

/// Stages `out`/mission.json (`source`: the scenario or scene.json planned; `edits`:
/// the edits file applied, if any) (pipeline_commands.cpp).
void writeMission(io::StagedOutputs& outputs, const std::string& out, const app::PlanResult& plan,
                  const app::Config& config, const std::string& source,
                  const std::optional<io::EditsSummary>& edits = std::nullopt);

/// --uavs K (K >= 0 when given) sets fleet.uavs and checks the config again
/// (pipeline_commands.cpp).
void setUavs(app::Config& config, int uavs);

/// Prints the fleet's makespan against the single flight and the bound, its separation
/// and each UAV (nothing without a fleet) (pipeline_commands.cpp).
void printFleet(const std::optional<planning::FleetPlan>& fleet);

/// "makespan M min (single UAV S min, speed-up X, lower bound B min)" of a fleet.
std::string fleetTimesText(const planning::FleetPlan& fleet);
/// "closest approach N m on schedule, W m with T s slack (separation D m)" of a fleet.
std::string fleetSeparationText(const planning::FleetPlan& fleet);

/// run, detect, plan (pipeline_commands.cpp).
void addPipelineCommands(CLI::App& cli, CommandRegistry& registry);

/// validate (validate_commands.cpp).
void addValidateCommands(CLI::App& cli, CommandRegistry& registry);

/// bench (bench_commands.cpp).
void addBenchCommands(CLI::App& cli, CommandRegistry& registry);

/// export (export_commands.cpp).
void addExportCommands(CLI::App& cli, CommandRegistry& registry);

/// simulate (and assemble, stages 1-2) (scan_commands.cpp).
void addScanCommands(CLI::App& cli, CommandRegistry& registry);

/// view: the 3D mission page (view_commands.cpp).
void addViewCommands(CLI::App& cli, CommandRegistry& registry);

/// tile, run-tile, merge: a large cloud in tiles (tile_commands.cpp).
void addTileCommands(CLI::App& cli, CommandRegistry& registry);

/// config --list: the scenario reference (config_commands.cpp).
void addConfigCommands(CLI::App& cli, CommandRegistry& registry);

/// photos: every photo stop rendered against a scenario's world (photo_commands.cpp).
void addPhotoCommands(CLI::App& cli, CommandRegistry& registry);

/// Renders the photos of `mission_path` against `world` into the folder `out`
/// (photo/photo_folder.h; `threads` 0: every core; `image_scale` in (0, 1] scales the
/// image size and pinhole); run --photos and photos.
int renderPlanPhotos(const std::string& mission_path, const sim::WorldModel& world,
                     const std::string& world_path, const std::string& out, int threads,
                     double image_scale, const Verbosity& v);

}  // namespace uavip::cli
