#pragma once
// Runs the built uavip executable as a user would, for the CLI tests.

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace uavip::cli_test {

/// Exit code and everything the command printed.
struct Result {
  int code{-1};
  std::string out;  ///< stdout and stderr together
};

/// Runs `uavip ARGS` (the binary of this build) and collects its output.
inline Result uavip(const std::string& args) {
  const std::string cmd = std::string(UAVIP_BINARY) + " " + args + " 2>&1";
  Result r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), pipe)) r.out += buf.data();
  const int status = ::pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// The whole content of a file ("" if missing).
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

}  // namespace uavip::cli_test
