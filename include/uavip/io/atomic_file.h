#pragma once
/// \file
/// Writing outputs without losing what was there: write a temporary file in the
/// same folder, then rename it over the target.

#include <functional>
#include <string>

namespace uavip::io {

/// Writes `text` to `path` atomically. Throws std::runtime_error naming the path.
void writeFileAtomic(const std::string& path, const std::string& text);

/// Calls write(tmp_path) then renames tmp_path to `path`; removes tmp_path if write throws.
void replaceFileAtomic(const std::string& path, const std::function<void(const std::string&)>& write);

/// Creates `dir` (and parents) if missing. Throws InputError if it is not a directory.
void ensureDirectory(const std::string& dir);

/// Reads a whole file. Throws InputError "<path>: cannot read …" if missing.
std::string readFile(const std::string& path);

}  // namespace uavip::io
