#pragma once
/// \file
/// Where `uavip run` without a file finds its bundled default scenario. Private to
/// src/cli.

#include <string>

namespace uavip::cli {

/// The directory of the bundled scenarios: the source tree's scenarios/ for build/uavip,
/// share/uavip/scenarios under the install prefix for the installed CLI. Its own unit,
/// scenario_dir.cpp, is the only source the installed CLI compiles again
/// (CMakeLists.txt).
std::string bundledScenarioDir();

}  // namespace uavip::cli
