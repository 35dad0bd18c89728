#include "uavip/sim/surface_sampler.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/memory.h"
#include "uavip/core/text.h"

namespace uavip::sim {

namespace {

/// Samples per edge of length `length`: ⌊length/spacing⌋ + 1 evenly spaced, both ends
/// included (at least 2, so both ends are kept even on an edge shorter than spacing).
/// The small tolerance keeps 2 m / 0.1 m at 21 despite rounding of 0.1.
int samplesAlong(double length, double spacing) {
  const int n = static_cast<int>(std::floor(length / spacing + 1e-9)) + 1;
  return std::max(n, 2);
}

/// Evenly spaced fraction i/(n−1) in [0, 1].
double fraction(int i, int n) { return static_cast<double>(i) / static_cast<double>(n - 1); }

/// Most points one sampling may draw (about 1.2 GB as doubles).
constexpr double kMaxSamples = 50e6;

}  // namespace

void SampleOptions::validate(const std::string& where) const {
  requirePositive(spacing_m, where, "spacing_m");
  requireThat(std::isfinite(noise_sigma_m) && noise_sigma_m >= 0.0, where, "noise_sigma_m", ">= 0",
              noise_sigma_m);
  requireThat(outlier_fraction >= 0.0 && outlier_fraction < 1.0, where, "outlier_fraction",
              "in [0, 1)", outlier_fraction);
  requireThat(std::isfinite(outlier_margin_m) && outlier_margin_m >= 0.0, where, "outlier_margin_m",
              ">= 0", outlier_margin_m);
}

PointList sampleSurfaces(const WorldModel& world, const SampleOptions& options) {
  options.validate();
  std::mt19937 rng(options.seed);
  // Standard normal draws scaled by sigma (sigma 0 is allowed and draws stay in step).
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double sigma = options.noise_sigma_m;
  const double spacing = options.spacing_m;

  // The count is known before any point is drawn: a tiny spacing on a large world
  // is refused instead of filling the memory.
  double expected = 0.0;
  for (const Rect& r : world.rects())
    expected += (r.edge_u.norm() / spacing + 1.0) * (r.edge_v.norm() / spacing + 1.0);
  for (const auto& seg : world.segments()) expected += (seg.b - seg.a).norm() / spacing + 1.0;
  if (!(expected <= kMaxSamples)) {
    std::ostringstream os;
    os << "spacing_m " << spacing << " m would sample about " << expected << " points, more than "
       << kMaxSamples << "; raise sensing.spacing_m";
    throw InputError(os.str());
  }
  requireMemory(expected * (1.0 + options.outlier_fraction) * sizeof(Vec3),
                "sampling about " + formatNumber(expected, 3) + " points",
                "raise sensing.spacing_m");

  PointList out;
  // Draw order: rectangles (in insertion order, s outer, t inner, one normal draw each),
  // segments (three draws x, y, z each), points (three draws each), then outliers.
  for (const Rect& r : world.rects()) {
    const Vec3 n = r.normal();
    const int nu = samplesAlong(r.edge_u.norm(), spacing);
    const int nv = samplesAlong(r.edge_v.norm(), spacing);
    out.reserve(out.size() + static_cast<size_t>(nu) * static_cast<size_t>(nv));
    for (int i = 0; i < nu; ++i) {
      for (int j = 0; j < nv; ++j) {
        const Vec3 p = r.corner + fraction(i, nu) * r.edge_u + fraction(j, nv) * r.edge_v;
        out.push_back(p + sigma * gauss(rng) * n);
      }
    }
  }
  auto isotropic = [&]() {
    const double x = gauss(rng);
    const double y = gauss(rng);
    const double z = gauss(rng);
    return Vec3(sigma * x, sigma * y, sigma * z);
  };
  for (const Segment& s : world.segments()) {
    const int n = samplesAlong((s.b - s.a).norm(), spacing);
    for (int i = 0; i < n; ++i) {
      const Vec3 p = s.a + fraction(i, n) * (s.b - s.a);
      out.push_back(p + isotropic());
    }
  }
  for (const TruthPoint& q : world.points()) out.push_back(q.p + isotropic());

  if (out.empty() || options.outlier_fraction <= 0.0) return out;
  const auto count =
      static_cast<size_t>(std::llround(options.outlier_fraction * static_cast<double>(out.size())));
  Aabb box = boundingBox(out);
  box.min.array() -= options.outlier_margin_m;
  box.max.array() += options.outlier_margin_m;
  const Vec3 size = box.max - box.min;
  out.reserve(out.size() + count);
  for (size_t k = 0; k < count; ++k) {
    const double x = uniform(rng);
    const double y = uniform(rng);
    const double z = uniform(rng);
    out.push_back(box.min + Vec3(x * size.x(), y * size.y(), z * size.z()));
  }
  return out;
}

}  // namespace uavip::sim
