// The ground truth of a scenario's world for benchmarks/photo_check.py: every rectangle of
// the world (sim::WorldModel, as the scenario loader builds it: planes, the six outward
// faces of each box, crossed planes, the boxes of trees and grass) as JSON on stdout,
//
//   uavip_world_truth SCENARIO.yaml
//   {"scenario": ..., "sensing_mode": "sample", "rects": [{"name": "cube/+x",
//    "corner": [x, y, z], "edge_u": [x, y, z], "edge_v": [x, y, z]}, ...]}
//
// in the scenario's frame [m] (the mission's local ENU frame in sensing mode `sample`).
// A rectangle is corner + s·edge_u + t·edge_v, s, t in [0, 1]; a box face's
// edge_u × edge_v points out of its box. Segments and points are left out (no surface).

#include <cstdio>
#include <iostream>
#include <string>

#include "uavip/app/scenario.h"
#include "uavip/core/error.h"

namespace {

std::string vec(const uavip::Vec3& v) {
  char s[96];
  std::snprintf(s, sizeof s, "[%.9g, %.9g, %.9g]", v.x(), v.y(), v.z());
  return s;
}

/// A JSON string literal of a name (quotes and backslashes escaped; names are plain text).
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out + "\"";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: uavip_world_truth SCENARIO.yaml\n";
    return 2;
  }
  try {
    const uavip::app::Scenario scenario = uavip::app::loadScenario(argv[1]);
    std::cout << "{\"scenario\": " << quoted(argv[1])
              << ", \"sensing_mode\": " << quoted(scenario.sensing_mode) << ", \"rects\": [";
    const auto& rects = scenario.world.rects();
    for (std::size_t i = 0; i < rects.size(); ++i) {
      const uavip::sim::Rect& r = rects[i];
      std::cout << (i ? ",\n  " : "\n  ") << "{\"name\": " << quoted(r.name)
                << ", \"corner\": " << vec(r.corner) << ", \"edge_u\": " << vec(r.edge_u)
                << ", \"edge_v\": " << vec(r.edge_v) << "}";
    }
    std::cout << "\n]}\n";
    return std::cout ? 0 : 1;
  } catch (const uavip::InputError& e) {
    std::cerr << "uavip_world_truth: error: " << e.what() << "\n";
    return 2;
  }
}
