#include "uavip/io/atomic_file.h"

#include <signal.h>
#include <sys/types.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/core/test_fault.h"

namespace uavip::io {

namespace fs = std::filesystem;

void replaceFileAtomic(const std::string& path,
                       const std::function<void(const std::string&)>& write) {
  StagedOutputs one;
  one.writeWith(path, write);
  one.commit();
}

namespace {

/// This host's name as temporaries carry it ('/' and '.' made '-'), then '-'.
const std::string& hostTag() {
  static const std::string host = [] {
    char name[256] = {};
    if (::gethostname(name, sizeof name - 1) != 0) return std::string();
    std::string h(name);
    for (char& c : h)
      if (c == '/' || c == '.') c = '-';
    return h + "-";
  }();
  return host;
}

/// The host and process in the name: two tasks of one array index on two nodes of a
/// shared file system (a task run twice) never write one temporary.
std::string temporaryFor(const std::string& path) {
  return path + ".tmp" + hostTag() + std::to_string(::getpid());
}

/// Removes the temporaries of `path` (temporaryFor) that a process of this host no
/// longer alive left behind (killed mid-write: SIGKILL, a node's OOM killer); those of
/// a live process, or of another host, stay. Each folder is listed once a process
/// (what is stale was left before it started), so staging n files costs O(n).
void removeStaleTemporaries(const std::string& path) {
  static std::mutex mutex;
  static std::map<std::string, std::vector<std::string>> listed;  // folder: this host's temporaries
  const fs::path target(path);
  const std::string dir = target.has_parent_path() ? target.parent_path().string() : ".";
  const std::string prefix = target.filename().string() + ".tmp" + hostTag();
  std::vector<std::string> stale;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    auto [at, fresh] = listed.try_emplace(dir);
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; fresh && !ec && it != end; it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (name.find(".tmp" + hostTag()) != std::string::npos) at->second.push_back(name);
    }
    for (const std::string& name : at->second) {
      if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
      const std::string digits = name.substr(prefix.size());
      if (digits.size() > 9 ||
          !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
        continue;
      const pid_t pid = static_cast<pid_t>(std::stol(digits));
      if (pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH) stale.push_back(name);
    }
  }
  std::error_code ec;
  for (const std::string& name : stale) fs::remove(fs::path(dir) / name, ec);
}

/// Writes `text` to `file`; messages name `path`, the file the user asked for.
void writeText(const std::string& file, const std::string& text, const std::string& path) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  out.close();
  if (!out)
    throw InputError(path +
                     ": cannot write (no permission, or the disk is full); choose another -o");
}

/// The checks before writing `path`: not a folder, its folder created.
void prepareTarget(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw InputError(path + ": is a directory; give a file name to write");
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty()) ensureDirectory(parent.string());
}

}  // namespace

void writeFileAtomic(const std::string& path, const std::string& text) {
  replaceFileAtomic(path, [&](const std::string& tmp) { writeText(tmp, text, path); });
}

StagedOutputs::~StagedOutputs() {
  std::error_code ec;
  for (const auto& s : staged_) fs::remove(s.first, ec);
}

void StagedOutputs::writeWith(const std::string& path,
                              const std::function<void(const std::string&)>& write) {
  prepareTarget(path);
  removeStaleTemporaries(path);
  const std::string tmp = temporaryFor(path);
  staged_.emplace_back(tmp, path);  // removed by the destructor unless committed
  write(tmp);
}

void StagedOutputs::write(const std::string& path, const std::string& text) {
  writeWith(path, [&](const std::string& tmp) { writeText(tmp, text, path); });
}

void StagedOutputs::commit() {
  const bool kill_half = core::faultArmed("kill-mid-write");  // the fault tests' hook
  for (std::size_t i = 0; i < staged_.size(); ++i) {
    if (kill_half && i == staged_.size() / 2) std::raise(SIGKILL);
    const auto& [tmp, path] = staged_[i];
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) throw InputError(path + ": cannot write (" + ec.message() + "); choose another -o");
  }
  staged_.clear();
}

void ensureDirectory(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec))
      throw InputError(dir + ": exists and is not a directory; choose another -o");
    return;
  }
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create the output directory (" + ec.message() + ")");
}

void requireDistinctOutputs(const std::vector<std::string>& inputs,
                            const std::vector<std::string>& outputs) {
  const auto key = [](const std::string& p) {
    std::error_code ec;
    const fs::path c = fs::weakly_canonical(fs::absolute(p, ec), ec);
    return ec ? fs::path(p).lexically_normal().string() : c.string();
  };
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const std::string o = key(outputs[i]);
    for (const auto& in : inputs) {
      if (key(in) == o)
        throw InputError(outputs[i] + ": would overwrite the input " + in + "; choose another -o");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (key(outputs[j]) == o)
        throw InputError(
            outputs[i] +
            ": two outputs of this command would be written to the same file; choose another -o");
    }
  }
}

void requireRegularFile(const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) throw InputError(path + ": no such file");
  if (fs::is_directory(st)) throw InputError(path + ": is a directory, expected a file");
  if (!fs::is_regular_file(st))
    throw InputError(
        path + ": is not a regular file (a device, pipe or socket); save the data to a file first");
}

std::string readFile(const std::string& path) {
  std::error_code ec;
  requireRegularFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read (permission?)");
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

}  // namespace uavip::io
