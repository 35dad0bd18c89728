// uavip photos: every photo stop of a mission rendered against the simulator's ground
// truth, with the COLMAP model and poses beside them (photo/photo_folder.h).

#include <iostream>
#include <memory>

#include "src/cli/commands.h"
#include "uavip/app/scenario.h"
#include "uavip/core/parallel.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"
#include "uavip/photo/photo_folder.h"

namespace uavip::cli {

int renderPlanPhotos(const std::string& mission_path, const sim::WorldModel& world,
                     const std::string& world_path, const std::string& out, int threads,
                     const Verbosity& v) {
  const io::MissionRecord mission = io::loadMission(mission_path);
  io::requireDistinctOutputs({mission_path, world_path}, {out + "/photos.json"});
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
  const photo::PhotoSummary s =
      photo::writePhotoFolder(mission, mission_path, world, world_path, out, options);
  if (!v.quiet) {
    std::cout << "photos: " << s.photos << " in " << out << "/images ("
              << formatFixed(s.megapixels, 1) << " MP, " << formatFixed(s.seconds, 2) << " s, "
              << formatFixed(s.seconds / std::max(s.megapixels, 1e-9), 3)
              << " s/MP); COLMAP model in " << out << "/sparse, poses.csv, photos.json\n"
              << "photos: targets on the world: " << (s.match.targets - s.match.far) << " of "
              << s.match.targets << " within " << formatNumber(s.match.tolerance_m, 3)
              << " m (median " << formatNumber(s.match.median_m, 3) << " m)\n";
  }
  return kExitOk;
}

namespace {

/// Options of photos, kept alive until dispatch.
struct PhotoArgs {
  std::string mission, world, out;
  int threads{0};
};

}  // namespace

void addPhotoCommands(CLI::App& cli, CommandRegistry& registry) {
  const auto [photos, a] = missionCommand<PhotoArgs>(
      cli, "photos",
      "Render every photo stop of the flight against a scenario's ground-truth world "
      "(PNG per stop, COLMAP text model, poses.csv)");
  const Verbosity& v = registry.verbosity();
  photos->add_option("--world", a->world, "Scenario YAML whose world the mission was planned on")
      ->required();
  photos->add_option("-o,--out", a->out, "Output folder (images/, sparse/, poses.csv, photos.json)")
      ->required();
  photos->add_option("--threads", a->threads, "Worker threads (default: every core)");
  registry.add(photos, [a = a, &v] {
    const app::Scenario scenario = app::loadScenario(a->world);
    return renderPlanPhotos(a->mission, scenario.world, a->world, a->out, a->threads, v);
  });
}

}  // namespace uavip::cli
