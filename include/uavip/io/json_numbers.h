#pragma once
/// \file
/// How scene.json, mission.json and the mission page write numbers: metres, degrees and
/// seconds rounded to 4 decimals (0.1 mm), which keeps the files short and diffable.

#include <cmath>
#include <nlohmann/json.hpp>

#include "uavip/core/types.h"

namespace uavip::io {

/// v rounded to 4 decimals.
inline double round4(double v) { return std::round(v * 1e4) / 1e4; }

/// [x, y, z] rounded to 4 decimals.
inline nlohmann::json vec(const Vec3& p) {
  return nlohmann::json::array({round4(p.x()), round4(p.y()), round4(p.z())});
}

}  // namespace uavip::io
