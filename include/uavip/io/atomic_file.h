#pragma once
/// \file
/// Writing outputs without losing what was there: write a temporary file in the
/// same folder, then rename it over the target.

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace uavip::io {

/// Writes `text` to `path` atomically, creating missing parent folders. Throws
/// InputError naming the path when it is a folder or cannot be written.
void writeFileAtomic(const std::string& path, const std::string& text);

/// Calls write(tmp_path) then renames tmp_path to `path`; removes tmp_path if write throws.
void replaceFileAtomic(const std::string& path,
                       const std::function<void(const std::string&)>& write);

/// The outputs of one command, written as one unit: each file goes to a temporary
/// beside its target, and commit() renames them all onto their targets. Destroyed
/// without commit (an error on the way), it removes its temporaries, so every
/// earlier output stays as it was and a folder never mixes two runs.
class StagedOutputs {
 public:
  StagedOutputs() = default;
  StagedOutputs(const StagedOutputs&) = delete;
  StagedOutputs& operator=(const StagedOutputs&) = delete;
  ~StagedOutputs();

  /// Stages `text` for `path` (creating its folder). Throws InputError naming the
  /// path when it is a folder or cannot be written.
  void write(const std::string& path, const std::string& text);
  /// Stages the file write(tmp_path) makes for `path`. Temporaries of `path` that a
  /// process of this host no longer running left (a task killed mid-write) are
  /// removed first; a live process's, or another host's, are left alone.
  void writeWith(const std::string& path, const std::function<void(const std::string&)>& write);
  /// Renames every staged file onto its target, in the order staged (the one a reader
  /// takes as the mark of a complete result goes last). Test hook: core/test_fault.h.
  void commit();
  /// The files staged so far: (temporary, target), in the order staged.
  const std::vector<std::pair<std::string, std::string>>& staged() const { return staged_; }

 private:
  std::vector<std::pair<std::string, std::string>> staged_;  ///< (temporary, target)
};

/// Creates `dir` (and parents) if missing. Throws InputError if it is not a directory.
void ensureDirectory(const std::string& dir);

/// Throws InputError naming the output when an output path is one of the inputs
/// (same file after resolving links and `..`) or two outputs are the same file.
void requireDistinctOutputs(const std::vector<std::string>& inputs,
                            const std::vector<std::string>& outputs);

/// Throws InputError naming `path` unless it is an existing regular file (not a
/// folder, device, pipe or socket: reading /dev/zero or a FIFO would never end).
void requireRegularFile(const std::string& path);

/// Reads a whole regular file (requireRegularFile). Throws InputError "<path>: …".
std::string readFile(const std::string& path);

}  // namespace uavip::io
