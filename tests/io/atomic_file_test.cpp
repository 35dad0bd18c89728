// Outputs written as one unit (io/atomic_file.h): staged files appear only on
// commit, and an error before commit leaves the earlier files and no temporaries.

#include "uavip/io/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "uavip/core/error.h"

namespace uavip::io {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// A fresh folder holding a.txt = "old a" and b.txt = "old b".
fs::path folder(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("uavip_staged_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  writeFileAtomic((dir / "a.txt").string(), "old a");
  writeFileAtomic((dir / "b.txt").string(), "old b");
  return dir;
}

std::size_t entries(const fs::path& dir) {
  return static_cast<std::size_t>(
      std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

TEST(StagedOutputs, FilesAppearTogetherOnCommit) {
  const fs::path dir = folder("commit");
  StagedOutputs out;
  out.write((dir / "a.txt").string(), "new a");
  out.write((dir / "sub" / "c.txt").string(), "new c");  // a missing folder is created
  EXPECT_EQ(slurp(dir / "a.txt"), "old a");
  EXPECT_FALSE(fs::exists(dir / "sub" / "c.txt"));
  out.commit();
  EXPECT_EQ(slurp(dir / "a.txt"), "new a");
  EXPECT_EQ(slurp(dir / "sub" / "c.txt"), "new c");
  EXPECT_EQ(slurp(dir / "b.txt"), "old b");
  EXPECT_EQ(entries(dir), 3u);  // a.txt, b.txt, sub: no temporaries left
}

/// This host's name as a temporary's name carries it, written out here.
std::string hostInName() {
  char name[256] = {};
  EXPECT_EQ(::gethostname(name, sizeof name - 1), 0);
  std::string h(name);
  for (char& c : h)
    if (c == '/' || c == '.') c = '-';
  return h;
}

TEST(StagedOutputs, AStaleTemporaryOfADeadProcessIsRemovedWhenItsTargetIsWritten) {
  // A folder this process has not written in yet (each folder is looked at once).
  const fs::path dir =
      fs::temp_directory_path() / ("uavip_staged_stale_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "b.txt") << "old b";
  const pid_t child = ::fork();  // a process of this host that is no longer alive
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ASSERT_EQ(::waitpid(child, nullptr, 0), child);
  const std::string host = hostInName(), dead = std::to_string(child);
  const std::string live = std::to_string(::getppid());
  const auto leave = [&](const std::string& name) { std::ofstream(dir / name) << "partial"; };
  leave("a.txt.tmp" + host + "-" + dead);            // a.txt's, by a dead process: stale
  leave("a.txt.tmp" + host + "-" + live);            // a.txt's, by a live process
  leave("a.txt.tmp" + host + "x-" + dead);           // a.txt's, by another host
  leave("b.txt.tmp" + host + "-" + dead);            // not an output of this run
  leave("a.txt.tmp" + host + "-" + dead + "-keep");  // not a temporary's name
  StagedOutputs out;
  out.write((dir / "a.txt").string(), "new a");
  EXPECT_FALSE(fs::exists(dir / ("a.txt.tmp" + host + "-" + dead)));
  out.commit();
  EXPECT_EQ(slurp(dir / "a.txt"), "new a");
  for (const std::string& kept :
       {"a.txt.tmp" + host + "-" + live, "a.txt.tmp" + host + "x-" + dead,
        "b.txt.tmp" + host + "-" + dead, "a.txt.tmp" + host + "-" + dead + "-keep"})
    EXPECT_TRUE(fs::exists(dir / kept)) << kept;
  EXPECT_EQ(entries(dir), 6u);  // a.txt, b.txt and the four kept
  fs::remove_all(dir);
}

TEST(StagedOutputs, AnErrorBeforeCommitLeavesTheEarlierFilesWhole) {
  const fs::path dir = folder("error");
  try {
    StagedOutputs out;
    out.write((dir / "a.txt").string(), "new a");
    out.writeWith((dir / "b.txt").string(), [](const std::string& tmp) {
      std::ofstream(tmp) << "half";
      throw std::runtime_error("the disk is full");
    });
    out.commit();
    FAIL() << "the error was swallowed";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "the disk is full");
  }
  EXPECT_EQ(slurp(dir / "a.txt"), "old a");
  EXPECT_EQ(slurp(dir / "b.txt"), "old b");
  EXPECT_EQ(entries(dir), 2u);  // the temporaries are gone
}

TEST(StagedOutputs, AFolderAsTargetIsNamed) {
  const fs::path dir = folder("folder");
  StagedOutputs out;
  try {
    out.write(dir.string(), "x");
    FAIL() << "a folder was accepted as a file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace uavip::io
