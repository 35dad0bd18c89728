#pragma once
/// \file
/// Small numeric helpers every stage uses: π and degree conversion, medians, angle
/// wrapping. Header-only.

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace uavip {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;  ///< [rad/deg]
constexpr double kRadToDeg = 180.0 / kPi;  ///< [deg/rad]
/// +∞, the "nothing found yet" distance of the nearest-point searches.
constexpr double kInf = std::numeric_limits<double>::infinity();
/// Quiet NaN, "no value" in records and statistics.
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

/// The element at index n/2 after sorting (the upper median for an even count),
/// found with nth_element; NaN for an empty vector.
inline double upperMedian(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

/// The median (the mean of the middle two for an even count); NaN for an empty vector.
inline double median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

/// Angle wrapped into (−π, π] [rad].
inline double wrapAngle(double a) {
  while (a > kPi) a -= 2.0 * kPi;
  while (a <= -kPi) a += 2.0 * kPi;
  return a;
}

}  // namespace uavip
