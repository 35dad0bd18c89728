#pragma once
/// \file
/// SHA-256 of a file's bytes (OpenSSL's EVP digest), recorded in scene.json so that a
/// later step can tell whether the input cloud it re-reads is the one detected.

#include <string>

namespace uavip::io {

/// Lower-case hex SHA-256 of the file at `path` (64 characters). Throws InputError
/// naming the file when it cannot be read.
std::string sha256File(const std::string& path);

}  // namespace uavip::io
