#pragma once
/// \file
/// The one strict JSON reader of uavip's files (scene.json, mission.json, the raw
/// log's log.json): every failure is an InputError "<file>: <field> <what>" naming
/// the field by its path (`surfaces[3].waypoints[7]`), never a nlohmann exception.
/// Numbers must be finite; coordinates of the local frame must lie within
/// ±kMaxLocalCoordinateM, so a point at 1e155 m is refused before any geometry
/// (a swept segment of that length overflows the collision queries). Lives in io/
/// rather than core/ so that core stays free of file formats.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "uavip/core/types.h"

namespace uavip::io {

/// Largest coordinate of a local ENU frame read from a file [m]: 1,000 km, far
/// beyond any UAV mission and small enough for exact segment queries.
constexpr double kMaxLocalCoordinateM = 1e6;

/// Strict access to one JSON document; `file` names it in every message.
class JsonReader {
 public:
  explicit JsonReader(std::string file) : file_(std::move(file)) {}

  const std::string& file() const { return file_; }

  /// Parses `text`; InputError "<file>:<line>: not valid JSON (byte B; …)".
  nlohmann::json parse(const std::string& text) const;
  /// Reads and parses the file (a regular file, see io::readFile).
  nlohmann::json load() const;

  /// Throws InputError "<file>: <field> <what>".
  [[noreturn]] void fail(const std::string& field, const std::string& what) const;

  /// `parent.key`; InputError "<parent.key> is missing" when absent or `j` is not an object.
  const nlohmann::json& at(const nlohmann::json& j, const std::string& key,
                           const std::string& parent) const;
  /// The list at `field`; InputError unless `j` is an array.
  const nlohmann::json& list(const nlohmann::json& j, const std::string& field) const;
  /// A finite number.
  double number(const nlohmann::json& j, const std::string& field) const;
  /// A finite number in [lo, hi]; the message gives the range and `unit`.
  double number(const nlohmann::json& j, const std::string& field, double lo, double hi,
                const std::string& unit) const;
  /// A whole number in [lo, hi].
  std::int64_t integer(const nlohmann::json& j, const std::string& field, std::int64_t lo,
                       std::int64_t hi) const;
  std::string text(const nlohmann::json& j, const std::string& field) const;
  bool boolean(const nlohmann::json& j, const std::string& field) const;
  /// [x, y, z] of finite numbers; with `local` each within ±kMaxLocalCoordinateM.
  Vec3 vec3(const nlohmann::json& j, const std::string& field, bool local = true) const;
  /// A list of vec3 (local coordinates).
  PointList points(const nlohmann::json& j, const std::string& field) const;

  /// "parent.key" or "key" for an empty parent; "parent[i]".
  static std::string join(const std::string& parent, const std::string& key);
  static std::string item(const std::string& parent, std::size_t i);

 private:
  std::string file_;
};

}  // namespace uavip::io
