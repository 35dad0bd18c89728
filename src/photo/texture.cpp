#include "uavip/photo/texture.h"

#include <algorithm>
#include <cmath>

#include "uavip/core/error.h"
#include "uavip/core/text.h"

namespace uavip::photo {
namespace {

/// splitmix64's finaliser: every input bit moves every output bit.
std::uint64_t mix64(std::uint64_t h) {
  h ^= h >> 30U;
  h *= 0xBF58476D1CE4E5B9ULL;
  h ^= h >> 27U;
  h *= 0x94D049BB133111EBULL;
  h ^= h >> 31U;
  return h;
}

/// Lattice value in [−1, 1] of cell (x, y, z) for the hash key `key`.
double latticeValue(std::int64_t x, std::int64_t y, std::int64_t z, std::uint64_t key) {
  const std::uint64_t h = mix64(key ^ (static_cast<std::uint64_t>(x) * 0xD6E8FEB86659FD93ULL) ^
                                (static_cast<std::uint64_t>(y) * 0xA0761D6478BD642FULL) ^
                                (static_cast<std::uint64_t>(z) * 0xE7037ED1A0B428DBULL));
  return static_cast<double>(h >> 11U) * (2.0 / 9007199254740992.0) - 1.0;  // 2^53
}

/// Quintic fade 6t⁵ − 15t⁴ + 10t³ (continuous first and second derivatives).
double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

double lerp(double a, double b, double t) { return a + (b - a) * t; }

}  // namespace

void TextureOptions::validate(const std::string& where) const {
  if (!(std::isfinite(finest_feature_m) && finest_feature_m > 0.0))
    throw InputError(where + ": finest_feature_m must be > 0, got " +
                     formatNumber(finest_feature_m));
  if (octaves < 1 || octaves > 16)
    throw InputError(where + ": octaves must lie in [1, 16], got " + std::to_string(octaves));
  if (!(persistence > 0.0 && persistence <= 1.0))
    throw InputError(where + ": persistence must lie in (0, 1], got " + formatNumber(persistence));
}

SurfaceTexture::SurfaceTexture(const TextureOptions& options) : options_(options) {
  options_.validate();
}

double SurfaceTexture::valueNoise(const Vec3& p, double spacing_m, std::uint32_t channel) const {
  const Vec3 q = p / spacing_m;
  const double fx = std::floor(q.x()), fy = std::floor(q.y()), fz = std::floor(q.z());
  const auto x = static_cast<std::int64_t>(fx), y = static_cast<std::int64_t>(fy),
             z = static_cast<std::int64_t>(fz);
  const double tx = fade(q.x() - fx), ty = fade(q.y() - fy), tz = fade(q.z() - fz);
  const std::uint64_t key = mix64((static_cast<std::uint64_t>(options_.seed) << 32U) ^
                                  static_cast<std::uint64_t>(channel));
  const double c00 = lerp(latticeValue(x, y, z, key), latticeValue(x + 1, y, z, key), tx);
  const double c10 = lerp(latticeValue(x, y + 1, z, key), latticeValue(x + 1, y + 1, z, key), tx);
  const double c01 = lerp(latticeValue(x, y, z + 1, key), latticeValue(x + 1, y, z + 1, key), tx);
  const double c11 =
      lerp(latticeValue(x, y + 1, z + 1, key), latticeValue(x + 1, y + 1, z + 1, key), tx);
  return lerp(lerp(c00, c10, ty), lerp(c01, c11, ty), tz);
}

std::array<float, 3> SurfaceTexture::albedo(const Vec3& p, double pixel_m) const {
  // Luminance: the octaves, coarsest first; finer ones fade out below 2 px.
  double sum = 0.0, norm = 0.0, amplitude = 1.0;
  double spacing = options_.finest_feature_m * std::ldexp(1.0, options_.octaves - 1);
  for (int k = 0; k < options_.octaves; ++k) {
    norm += amplitude;
    const double weight = amplitude * std::clamp(spacing / pixel_m - 1.0, 0.0, 1.0);
    if (weight > 0.0) sum += weight * valueNoise(p, spacing, static_cast<std::uint32_t>(k));
    amplitude *= options_.persistence;
    spacing *= 0.5;
  }
  const double lum = std::clamp(0.5 + 1.2 * sum / norm, 0.04, 0.96);
  // Tint: one lattice four times coarser than the coarsest octave mixes two stone colours.
  const double coarsest = options_.finest_feature_m * std::ldexp(1.0, options_.octaves + 1);
  const double t = 0.5 + 0.5 * valueNoise(p, coarsest, 1000U);
  const std::array<double, 3> warm{1.08, 1.0, 0.88}, cool{0.9, 0.98, 1.1};
  std::array<float, 3> rgb{};
  for (int c = 0; c < 3; ++c)
    rgb[static_cast<std::size_t>(c)] = static_cast<float>(std::clamp(
        lum * lerp(warm[static_cast<std::size_t>(c)], cool[static_cast<std::size_t>(c)], t), 0.0,
        1.0));
  return rgb;
}

}  // namespace uavip::photo
