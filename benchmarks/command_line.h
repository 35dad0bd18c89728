#pragma once
// A benchmark's command line: scenario paths and `--NAME VALUE` options (header-only;
// not part of the library).

#include <algorithm>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace uavip::bench_util {

/// Scenario paths and the options given.
struct CommandLine {
  std::vector<std::string> paths;             ///< every argument that is not an option
  std::map<std::string, std::string> values;  ///< the last value of each option given

  /// Option `name` as a count (at least 1), or `fallback` when it was not given.
  int count(const std::string& name, int fallback) const {
    const auto it = values.find(name);
    return it == values.end() ? fallback : std::max(1, std::atoi(it->second.c_str()));
  }
  /// Option `name` as a number, or `fallback` when it was not given.
  double number(const std::string& name, double fallback) const {
    const auto it = values.find(name);
    return it == values.end() ? fallback : std::atof(it->second.c_str());
  }
};

/// Reads argv: an argument of `options` followed by another takes that one as its
/// value; every other argument is a path. `default_paths` when no path was given.
inline CommandLine parseCommandLine(int argc, char** argv, const std::vector<std::string>& options,
                                    std::vector<std::string> default_paths) {
  CommandLine c;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 < argc && std::find(options.begin(), options.end(), a) != options.end()) {
      c.values[a] = argv[++i];
    } else {
      c.paths.push_back(a);
    }
  }
  if (c.paths.empty()) c.paths = std::move(default_paths);
  return c;
}

}  // namespace uavip::bench_util
