#pragma once
/// \file
/// The texture fixed to the ground-truth world's surfaces (issue 46): a seeded,
/// multi-octave 3D value noise evaluated at the surface point itself, so the same
/// point has the same colour in every photo (no UV map, no view dependence).
///
/// Octave k (k = 0 … octaves−1) is value noise on a cubic lattice of spacing
/// s_k = finest_feature_m · 2^(octaves−1−k) (k = octaves−1 is the finest), with weight
/// a_k = persistence^(octaves−1−k) · fade_k, fade_k = clamp(s_k / pixel_m − 1, 0, 1):
/// an octave whose lattice is finer than 2 px of the photo fades out and one under
/// 1 px is left out (the band limit a mip-map gives; what a farther view sees is a
/// blurred version of the same texture). Lattice values come from a 64-bit hash of
/// (cell, octave, seed): no period and no mark unique to one place.

#include <array>
#include <cstdint>
#include <string>

#include "uavip/core/types.h"

namespace uavip::photo {

/// Parameters of the world's texture.
struct TextureOptions {
  std::uint32_t seed{46};          ///< the noise's seed
  double finest_feature_m{0.002};  ///< lattice spacing of the finest octave [m]
  int octaves{6};                  ///< octaves, each twice the spacing of the next finer
  double persistence{0.75};        ///< weight of an octave relative to the next coarser one

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "texture") const;
};

/// View-independent albedo of world points. Immutable after construction; every
/// const member is thread-safe.
class SurfaceTexture {
 public:
  explicit SurfaceTexture(const TextureOptions& options);

  /// Linear RGB albedo in [0, 1] of world point p [m] seen with a pixel footprint of
  /// pixel_m [m] (the range divided by the focal length in pixels).
  std::array<float, 3> albedo(const Vec3& p, double pixel_m) const;

  /// Value noise of one lattice of spacing spacing_m [m] at p, in [−1, 1]; `channel`
  /// picks an independent lattice (hash input).
  double valueNoise(const Vec3& p, double spacing_m, std::uint32_t channel) const;

  const TextureOptions& options() const { return options_; }

 private:
  TextureOptions options_;
};

}  // namespace uavip::photo
