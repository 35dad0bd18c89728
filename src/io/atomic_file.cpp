#include "uavip/io/atomic_file.h"

#include "uavip/core/error.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace uavip::io {

namespace fs = std::filesystem;

void replaceFileAtomic(const std::string& path, const std::function<void(const std::string&)>& write) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(path + ": is a directory; give a file name to write");
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty()) ensureDirectory(parent.string());
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  try {
    write(tmp);
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(path + ": cannot write (" + ec.message() + "); choose another -o");
  }
}

void writeFileAtomic(const std::string& path, const std::string& text) {
  replaceFileAtomic(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.close();
    if (!out) throw InputError(path + ": cannot write (no permission, or the disk is full); choose another -o");
  });
}

void ensureDirectory(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) throw InputError(dir + ": exists and is not a directory; choose another -o");
    return;
  }
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create the output directory (" + ec.message() + ")");
}

void requireDistinctOutputs(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs) {
  const auto key = [](const std::string& p) {
    std::error_code ec;
    const fs::path c = fs::weakly_canonical(fs::absolute(p, ec), ec);
    return ec ? fs::path(p).lexically_normal().string() : c.string();
  };
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const std::string o = key(outputs[i]);
    for (const auto& in : inputs) {
      if (key(in) == o) throw InputError(outputs[i] + ": would overwrite the input " + in + "; choose another -o");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (key(outputs[j]) == o)
        throw InputError(outputs[i] + ": two outputs of this command would be written to the same file; choose another -o");
    }
  }
}

void requireRegularFile(const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) throw InputError(path + ": no such file");
  if (fs::is_directory(st)) throw InputError(path + ": is a directory, expected a file");
  if (!fs::is_regular_file(st))
    throw InputError(path + ": is not a regular file (a device, pipe or socket); save the data to a file first");
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
