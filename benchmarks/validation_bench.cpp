// uavip_validation_bench: the merge's streamed validation (every sortie against every
// input point), indexed (app::clearanceToCloud) against the chunk-by-sortie loop it
// replaced, on the same flights; both must give the same clearances.
//
//   uavip_validation_bench CLOUD SECTION_JSON... [--repeat N --shift DX] [--cutoff M]
//
// The flights are read from plan-section's section.json files; --repeat copies them N
// times shifted by DX metres in x (the viaduct of uavip_site_cloud repeats along x, so
// the 0.5 km site's flights fly a 4 km viaduct 7 times over). Prints the sorties, the
// segments, the points and both wall times; exit 1 when a clearance differs.
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "uavip/app/site.h"
#include "uavip/io/atomic_file.h"
#include "uavip/io/cloud_io.h"
#include "uavip/planning/path_validator.h"

namespace {

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

int run(int argc, char** argv) {
  using uavip::Vec3;
  std::vector<std::string> files;
  int repeat = 1;
  double shift = 0.0, cutoff = 10.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--repeat" && i + 1 < argc) {
      repeat = std::atoi(argv[++i]);
    } else if (a == "--shift" && i + 1 < argc) {
      shift = std::atof(argv[++i]);
    } else if (a == "--cutoff" && i + 1 < argc) {
      cutoff = std::atof(argv[++i]);
    } else {
      files.push_back(a);
    }
  }
  if (files.size() < 2) {
    std::cerr << "usage: uavip_validation_bench CLOUD SECTION_JSON... [--repeat N --shift DX] "
                 "[--cutoff M]\n";
    return 2;
  }
  std::vector<uavip::planning::FlightPlan> plans;
  std::size_t segments = 0, sorties = 0;
  for (int r = 0; r < repeat; ++r)
    for (std::size_t f = 1; f < files.size(); ++f) {
      const auto j = nlohmann::json::parse(uavip::io::readFile(files[f]));
      uavip::planning::FlightPlan plan;
      for (const auto& s : j.at("summary").at("flight").at("sorties")) {
        uavip::planning::Sortie sortie;
        for (const auto& w : s)
          sortie.waypoints.emplace_back(w.at(0).get<double>() + shift * r, w.at(1).get<double>(),
                                        w.at(2).get<double>());
        segments += sortie.waypoints.size() - 1;
        ++sorties;
        plan.sorties.push_back(std::move(sortie));
      }
      plans.push_back(std::move(plan));
    }
  std::vector<const uavip::planning::FlightPlan*> flights;
  flights.reserve(plans.size());
  for (const auto& p : plans) flights.push_back(&p);
  const uavip::io::CloudReadOptions read;
  constexpr std::size_t kChunk = std::size_t{1} << 21;  // as the merge streams

  auto t0 = std::chrono::steady_clock::now();
  std::uint64_t points = 0;
  const auto indexed =
      uavip::app::clearanceToCloud(files[0], read, flights, cutoff, kChunk, nullptr, &points);
  const double indexed_s = since(t0);

  t0 = std::chrono::steady_clock::now();
  std::vector<std::vector<double>> loop(plans.size());
  for (std::size_t f = 0; f < plans.size(); ++f)
    loop[f].assign(plans[f].sorties.size(), std::numeric_limits<double>::infinity());
  std::size_t chunks = 0;
  uavip::io::streamCloud(files[0], read, kChunk, [&](const uavip::PointList& chunk) {
    ++chunks;
    const uavip::planning::PathValidator validator(chunk, 0.6);
    for (std::size_t f = 0; f < plans.size(); ++f)
      for (std::size_t s = 0; s < plans[f].sorties.size(); ++s)
        loop[f][s] =
            std::min(loop[f][s], validator.validate(plans[f].sorties[s].waypoints).min_clearance_m);
  });
  const double loop_s = since(t0);

  t0 = std::chrono::steady_clock::now();
  uavip::io::streamCloud(files[0], read, kChunk, [](const uavip::PointList&) {});
  const double read_s = since(t0);
  std::cout << points << " points in " << chunks << " chunks, " << sorties << " sorties, "
            << segments << " segments: indexed " << indexed_s << " s, chunk x sortie loop "
            << loop_s << " s, reading alone " << read_s << " s\n";
  return indexed == loop ? 0 : (std::cerr << "clearances differ\n", 1);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "uavip_validation_bench: " << e.what() << "\n";
    return 2;
  }
}
