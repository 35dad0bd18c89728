#include "uavip/io/json_reader.h"

#include <algorithm>
#include <cmath>

#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"

namespace uavip::io {

using nlohmann::json;

std::string JsonReader::join(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string JsonReader::item(const std::string& parent, std::size_t i) {
  return parent + "[" + std::to_string(i) + "]";
}

json JsonReader::parse(const std::string& text) const {
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    const std::size_t byte = std::min<std::size_t>(e.byte, text.size());
    const auto line =
        1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(byte), '\n');
    throw InputError(file_ + ":" + std::to_string(line) + ": not valid JSON (byte " +
                     std::to_string(e.byte) + "; truncated or edited?)");
  } catch (const json::exception&
               e) {  // e.g. a number beyond a double (1e999): out_of_range, not parse_error
    throw InputError(file_ + ": not valid JSON (" + std::string(e.what()).substr(0, 120) + ")");
  }
}

json JsonReader::load() const { return parse(readFile(file_)); }

void JsonReader::fail(const std::string& field, const std::string& what) const {
  throw InputError(file_ + ": " + field + " " + what);
}

const json& JsonReader::at(const json& j, const std::string& key, const std::string& parent) const {
  if (!j.is_object() || !j.contains(key)) fail(join(parent, key), "is missing");
  return j.at(key);
}

const json& JsonReader::list(const json& j, const std::string& field) const {
  if (!j.is_array()) fail(field, "must be a list");
  return j;
}

double JsonReader::number(const json& j, const std::string& field) const {
  if (!j.is_number()) fail(field, "must be a number, got " + j.dump().substr(0, 40));
  const double v = j.get<double>();
  if (!std::isfinite(v)) fail(field, "must be finite");
  return v;
}

double JsonReader::number(const json& j, const std::string& field, double lo, double hi,
                          const std::string& unit) const {
  const double v = number(j, field);
  if (v < lo || v > hi)
    fail(field, "must be in [" + formatNumber(lo) + ", " + formatNumber(hi) + "] " + unit +
                    ", got " + formatNumber(v, 9));
  return v;
}

std::int64_t JsonReader::integer(const json& j, const std::string& field, std::int64_t lo,
                                 std::int64_t hi) const {
  const bool whole =
      j.is_number_integer() &&
      !(j.is_number_unsigned() && j.get<std::uint64_t>() > static_cast<std::uint64_t>(hi));
  if (!whole || j.get<std::int64_t>() < lo || j.get<std::int64_t>() > hi)
    fail(field, "must be a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                    "], got " + j.dump().substr(0, 40));
  return j.get<std::int64_t>();
}

std::string JsonReader::text(const json& j, const std::string& field) const {
  if (!j.is_string()) fail(field, "must be a string, got " + j.dump().substr(0, 40));
  return j.get<std::string>();
}

bool JsonReader::boolean(const json& j, const std::string& field) const {
  if (!j.is_boolean()) fail(field, "must be true or false");
  return j.get<bool>();
}

Vec3 JsonReader::vec3(const json& j, const std::string& field, bool local) const {
  if (!j.is_array() || j.size() != 3) fail(field, "must be [x, y, z]");
  Vec3 p;
  for (std::size_t i = 0; i < 3; ++i) {
    if (!j[i].is_number()) fail(field, "must hold numbers");
    p[static_cast<int>(i)] = j[i].get<double>();
  }
  if (!p.allFinite()) fail(field, "must be finite");
  if (local && p.cwiseAbs().maxCoeff() > kMaxLocalCoordinateM)
    fail(field, formatRawPoint(p) + " lies beyond " + formatNumber(kMaxLocalCoordinateM) +
                    " m of the local origin; coordinates are local metres");
  return p;
}

PointList JsonReader::points(const json& j, const std::string& field) const {
  if (!j.is_array()) fail(field, "must be a list of [x, y, z]");
  PointList out;
  out.reserve(j.size());
  for (std::size_t i = 0; i < j.size(); ++i) out.push_back(vec3(j[i], item(field, i)));
  return out;
}

}  // namespace uavip::io
