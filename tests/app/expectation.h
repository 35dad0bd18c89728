#pragma once
/// \file
/// A scenario's `expect:` section: what the paper reports for it (surface count,
/// every surface's mission status, the smallest surface area), asserted by
/// tests/app/scenarios_test.cpp. uavip itself does not read the section.

#include <yaml-cpp/yaml.h>

#include <optional>
#include <stdexcept>
#include <string>

namespace uavip::test {

/// The expected outcome of a scenario; every field optional.
struct Expectation {
  std::optional<int> surfaces;                ///< number of detected surfaces
  std::optional<std::string> status;          ///< mission status of every surface ("ok", "blocked")
  std::optional<double> min_surface_area_m2;  ///< smallest detected surface area [m²]

  bool empty() const { return !surfaces && !status && !min_surface_area_m2; }
};

/// Reads the `expect:` section of the scenario file at `path` (empty when it has
/// none). Throws std::runtime_error naming the file for an unknown key or a value
/// of the wrong type, so a typo in a scenario fails the test instead of passing it.
inline Expectation readExpectation(const std::string& path) {
  const YAML::Node expect = YAML::LoadFile(path)["expect"];
  Expectation e;
  if (!expect.IsDefined()) return e;
  if (!expect.IsMap()) throw std::runtime_error(path + ": expect must be a mapping");
  for (const auto& kv : expect) {
    const std::string key = kv.first.as<std::string>();
    try {
      if (key == "surfaces")
        e.surfaces = kv.second.as<int>();
      else if (key == "status")
        e.status = kv.second.as<std::string>();
      else if (key == "min_surface_area_m2")
        e.min_surface_area_m2 = kv.second.as<double>();
      else
        throw std::runtime_error(path + ": expect." + key + " is not a known key");
    } catch (const YAML::Exception& ex) {
      throw std::runtime_error(path + ": expect." + key + ": " + ex.what());
    }
  }
  return e;
}

}  // namespace uavip::test
