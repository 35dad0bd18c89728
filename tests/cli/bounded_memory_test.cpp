// Inputs whose size would fill the memory, run as a user runs them, each in its own
// child process: a world 1e9 m from the origin (recentred, planned), a 1e-9 m voxel
// and a 1e-9 m planning grid (refused, exit 2), a raw log of 200 stations (assembled
// in bounded memory) and the same log under a small --max-memory (refused). Each
// child's peak memory (wait4's ru_maxrss, which covers what it waited for) stays
// within 1 GB.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.h"

namespace {

namespace fs = std::filesystem;

/// Exit code, output and peak resident memory of one run.
struct Measured {
  int code{-1};
  std::string out;
  double peak_bytes{0.0};
};

/// Runs `uavip ARGS…` (no shell) with its output in a file; the peak RSS from wait4.
Measured runMeasured(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> argv{UAVIP_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  Measured m;
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    std::vector<char*> c;
    for (auto& a : argv) c.push_back(a.data());
    c.push_back(nullptr);
    ::execv(c[0], c.data());
    ::_exit(127);
  }
  int status = 0;
  rusage ru{};
  if (pid < 0 || ::wait4(pid, &status, 0, &ru) != pid) return m;
  m.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  m.peak_bytes = static_cast<double>(ru.ru_maxrss) * 1024.0;  // kB on Linux
  m.out = uavip::cli_test::slurp(log);
  return m;
}

constexpr double kMaxPeakBytes = 1e9;

/// The single-plane wall with `replace` applied to the bundled scenario's text.
std::string wallScenario(const std::string& from, const std::string& to) {
  std::string s =
      uavip::cli_test::slurp(fs::path(UAVIP_SOURCE_DIR) / "scenarios" / "single_plane.yaml");
  const std::size_t at = s.find(from);
  return at == std::string::npos ? "" : s.replace(at, from.size(), to);
}

class BoundedMemory : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("uavip_bounded_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  static inline fs::path dir_;
};

TEST_F(BoundedMemory, AWorldFarFromTheOriginIsRecentredAndPlanned) {
  const std::string far = wallScenario("corner: [0.0, 0.0, 0.5]", "corner: [1.0e9, 1.0e9, 0.5]");
  ASSERT_FALSE(far.empty());
  const std::string text = far.substr(0, far.find("  viewpoint:")) +
                           "  viewpoint: [1000000004.0, 999999994.0, 2.5]\n" +
                           far.substr(far.find('\n', far.find("  viewpoint:")) + 1);
  const fs::path scenario = write("far.yaml", text);
  const Measured m = runMeasured(
      {"run", scenario.string(), "--no-views", "-o", (dir_ / "far").string()}, dir_ / "far.log");
  EXPECT_EQ(m.code, 0) << m.out;
  EXPECT_NE(m.out.find("far from the origin"), std::string::npos) << m.out;
  EXPECT_LE(m.peak_bytes, kMaxPeakBytes);
  // The scene records the shift: the wall's corner rounded to whole metres.
  const std::string scene = uavip::cli_test::slurp(dir_ / "far" / "scene.json");
  const std::size_t offset = scene.find("\"source_offset_m\"");
  ASSERT_NE(offset, std::string::npos);
  EXPECT_EQ(scene.find("1000000004", offset), scene.find_first_of("0123456789", offset));
}

TEST_F(BoundedMemory, ANanometreVoxelIsRefusedAtOnce) {
  const fs::path scenario = write("voxel.yaml", wallScenario("voxel_m: 0.05", "voxel_m: 1.0e-9"));
  const Measured m =
      runMeasured({"run", scenario.string(), "--no-views", "-o", (dir_ / "voxel").string()},
                  dir_ / "voxel.log");
  EXPECT_EQ(m.code, 2) << m.out;
  EXPECT_NE(m.out.find("voxel_m"), std::string::npos) << m.out;
  EXPECT_LE(m.peak_bytes, kMaxPeakBytes);
}

TEST_F(BoundedMemory, ANanometreGridIsRefusedAtOnce) {
  const fs::path scenario =
      write("grid.yaml", wallScenario("resolution_m: 0.2", "resolution_m: 1.0e-9"));
  const Measured m = runMeasured(
      {"run", scenario.string(), "--no-views", "-o", (dir_ / "grid").string()}, dir_ / "grid.log");
  EXPECT_EQ(m.code, 2) << m.out;
  EXPECT_NE(m.out.find("grid.resolution_m"), std::string::npos) << m.out;
  EXPECT_LE(m.peak_bytes, kMaxPeakBytes);
}

TEST_F(BoundedMemory, TwoHundredStationsAreAssembledInBoundedMemory) {
  // The room of the assemble test, 200 stations on a grid inside it, a fast turn.
  std::ostringstream stations;
  for (int i = 0; i < 200; ++i) {
    stations << (i ? ", " : "") << "[" << -2.5 + (i % 10) * 0.6 << ", "
             << -1.5 + ((i / 10) % 5) * 0.7 << ", " << (i / 50) * 0.3 - 0.3 << "]";
  }
  const fs::path scenario =
      write("room200.yaml",
            "name: room200\nworld:\n"
            "  - {type: box, name: room, min: [-4, -3, -1.5], max: [5, 4, 2.5]}\n"
            "  - {type: box, name: pillar, min: [2, 1.5, -1.5], max: [2.6, 2.1, 2.5]}\n"
            "  - {type: box, name: crate, min: [-3, -2.5, -1.5], max: [-2, -1.7, -0.7], yaw_deg: "
            "20}\n"
            "sensing:\n  mode: scan\n  stations: [" +
                stations.str() + "]\n  yaw_rate_deg_s: 360\n  seed: 5\n");
  const fs::path scans = dir_ / "scans200";
  const Measured sim =
      runMeasured({"-q", "simulate", scenario.string(), "-o", scans.string()}, dir_ / "sim.log");
  ASSERT_EQ(sim.code, 0) << sim.out;

  const Measured m = runMeasured(
      {"-q", "assemble", scans.string(), "-o", (dir_ / "room200.pcd").string()}, dir_ / "a.log");
  EXPECT_EQ(m.code, 0) << m.out;
  EXPECT_LE(m.peak_bytes, kMaxPeakBytes);
  const std::string report = uavip::cli_test::slurp(dir_ / "room200.report.json");
  EXPECT_NE(report.find("\"id\": 199"), std::string::npos);

  // Under a budget smaller than a batch of stations: refused before the first is read.
  const Measured small = runMeasured(
      {"--max-memory", "20M", "assemble", scans.string(), "-o", (dir_ / "small.pcd").string()},
      dir_ / "small.log");
  EXPECT_EQ(small.code, 2) << small.out;
  EXPECT_NE(small.out.find("--max-memory"), std::string::npos) << small.out;
  EXPECT_FALSE(fs::exists(dir_ / "small.pcd"));
}

TEST_F(BoundedMemory, AMemorySizeThatIsNoSizeIsRefused) {
  const Measured m = runMeasured({"--max-memory", "lots", "config", "--list"}, dir_ / "lots.log");
  EXPECT_EQ(m.code, 2) << m.out;
  EXPECT_NE(m.out.find("'lots' is not a memory size"), std::string::npos) << m.out;
}

}  // namespace
