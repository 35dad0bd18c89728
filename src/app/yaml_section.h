#pragma once
// The strict YAML mapping reader of the scenario, config and edits files (app/ only,
// not installed): every key must be consumed, types are checked, and every message
// names the file and the key path.

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>
#include <sstream>
#include <string>

#include "uavip/core/error.h"
#include "uavip/core/types.h"

namespace uavip::app::yaml {

/// A YAML mapping read strictly: every key must be consumed, types are checked, and
/// every message names the file and the key path.
class Section {
 public:
  Section(const YAML::Node& node, std::string file, std::string path)
      : node_(node), file_(std::move(file)), path_(std::move(path)) {
    if (!node_.IsMap()) fail("", "must be a mapping (key: value)");
  }

  bool has(const std::string& key) {
    known_.insert(key);
    return node_[key].IsDefined() && !node_[key].IsNull();
  }

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw InputError(file_ + ": " + where(key) + " " + what);
  }

  std::string where(const std::string& key) const {
    if (path_.empty()) return key.empty() ? std::string("top level") : key;
    return key.empty() ? path_ : path_ + "." + key;
  }

  double number(const std::string& key) {
    const YAML::Node n = get(key);
    double v = 0.0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, v)) {
      fail(key, "must be a number, got '" + dump(n) + "'");
    }
    if (!std::isfinite(v)) fail(key, "must be finite, got " + dump(n));
    return v;
  }
  double number(const std::string& key, double fallback) {
    return has(key) ? number(key) : fallback;
  }

  int integer(const std::string& key, int fallback) {
    if (!has(key)) return fallback;
    const YAML::Node n = get(key);
    long long v = 0;
    if (!n.IsScalar() || !YAML::convert<long long>::decode(n, v)) {
      fail(key, "must be an integer, got '" + dump(n) + "'");
    }
    if (v < -2147483647LL || v > 2147483647LL) fail(key, "is out of range: " + dump(n));
    return static_cast<int>(v);
  }

  bool boolean(const std::string& key, bool fallback) {
    if (!has(key)) return fallback;
    const YAML::Node n = get(key);
    bool v = false;
    if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v)) {
      fail(key, "must be true or false, got '" + dump(n) + "'");
    }
    return v;
  }

  std::string text(const std::string& key) {
    const YAML::Node n = get(key);
    if (!n.IsScalar()) fail(key, "must be a string");
    return n.Scalar();
  }
  std::string text(const std::string& key, const std::string& fallback) {
    return has(key) ? text(key) : fallback;
  }

  std::vector<double> numbers(const std::string& key, std::size_t min_count,
                              std::size_t max_count) {
    const YAML::Node n = get(key);
    if (!n.IsSequence() || n.size() < min_count || n.size() > max_count) {
      std::ostringstream os;
      os << "must be a list of " << min_count;
      if (max_count != min_count) os << " to " << max_count;
      os << " numbers, got '" << dump(n) << "'";
      fail(key, os.str());
    }
    std::vector<double> out;
    for (const auto& item : n) {
      double v = 0.0;
      if (!item.IsScalar() || !YAML::convert<double>::decode(item, v) || !std::isfinite(v)) {
        fail(key, "must hold finite numbers, got '" + dump(n) + "'");
      }
      out.push_back(v);
    }
    return out;
  }

  Vec3 vec3(const std::string& key) {
    const auto v = numbers(key, 3, 3);
    return {v[0], v[1], v[2]};
  }
  Vec3 vec3(const std::string& key, const Vec3& fallback) {
    return has(key) ? vec3(key) : fallback;
  }

  /// A list of [x, y, z] points.
  PointList vec3List(const std::string& key) {
    const YAML::Node n = get(key);
    if (!n.IsSequence()) fail(key, "must be a list of [x, y, z]");
    PointList out;
    for (std::size_t i = 0; i < n.size(); ++i) {
      Vec3 v;
      if (!n[i].IsSequence() || n[i].size() != 3)
        fail(key, "must be a list of [x, y, z], item " + std::to_string(i) + " is not");
      for (int k = 0; k < 3; ++k) {
        if (!YAML::convert<double>::decode(n[i][k], v[k]) || !std::isfinite(v[k])) {
          fail(key, "item " + std::to_string(i) + " must hold finite numbers");
        }
      }
      out.push_back(v);
    }
    return out;
  }

  Section child(const std::string& key) { return Section(get(key), file_, where(key)); }

  /// Throws for any key that was never asked for (typos, unsupported options) and
  /// for a key given twice (yaml-cpp would silently keep the first).
  void finish() const {
    std::set<std::string> seen;
    for (const auto& kv : node_) {
      if (!kv.first.IsScalar())
        fail("", "has a key that is not a plain name (line " +
                     std::to_string(kv.first.Mark().line + 1) + ")");
      const std::string key = kv.first.as<std::string>();
      if (!seen.insert(key).second) {
        fail(key,
             "is given twice (line " + std::to_string(kv.first.Mark().line + 1) + "); keep one");
      }
      if (!known_.count(key)) {
        std::string valid;
        for (const auto& k : known_) valid += (valid.empty() ? "" : ", ") + k;
        fail(key, "is not a known key (valid here: " + valid + ")");
      }
    }
  }

  const YAML::Node& node() const { return node_; }
  /// 1-based line of the mapping in its file (0 when unknown).
  int line() const { return node_.Mark().line >= 0 ? node_.Mark().line + 1 : 0; }
  const std::string& file() const { return file_; }

 private:
  YAML::Node get(const std::string& key) {
    known_.insert(key);
    const YAML::Node n = node_[key];
    if (!n.IsDefined() || n.IsNull()) fail(key, "is missing");
    return n;
  }

  static std::string dump(const YAML::Node& n) {
    YAML::Emitter e;
    e << YAML::Flow << n;
    return e.c_str();
  }

  YAML::Node node_;
  std::string file_;
  std::string path_;
  std::set<std::string> known_;
};

}  // namespace uavip::app::yaml
