#pragma once
/// \file
/// Numbers and points as text for messages, summaries and text files: the one set
/// of formatters every module uses. Header-only.

#include "uavip/core/types.h"

#include <iomanip>
#include <sstream>
#include <string>

namespace uavip {

/// `v` with `digits` significant digits, as a stream prints it (6 is the stream's
/// default: 0.1, 1e+12, nan).
inline std::string formatNumber(double v, int digits = 6) {
  std::ostringstream os;
  os << std::setprecision(digits) << v;
  return os.str();
}

/// `v` with `decimals` digits after the point (1.50).
inline std::string formatFixed(double v, int decimals) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(decimals) << v;
  return os.str();
}

/// "(x, y, z)" in metres with two decimals: a position in a message.
inline std::string formatPoint(const Vec3& p) {
  return "(" + formatFixed(p.x(), 2) + ", " + formatFixed(p.y(), 2) + ", " + formatFixed(p.z(), 2) + ")";
}

/// "(x, y, z)" with 6 significant digits: a raw value that may be huge or NaN.
inline std::string formatRawPoint(const Vec3& p) {
  return "(" + formatNumber(p.x()) + ", " + formatNumber(p.y()) + ", " + formatNumber(p.z()) + ")";
}

}  // namespace uavip
