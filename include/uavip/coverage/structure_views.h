#pragma once
/// \file
/// Structure coverage (docs/ARCHITECTURE.md, "Structure coverage"): one view
/// selection over every point of a structure, planes, curved, thin and small parts
/// alike, instead of the paper's plane-by-plane rows (§II-F).
///
/// Normals: oriented toward the free space the camera can reach; where both sides
/// can be reached (a thin wall, a panel) or neither is known, the point's flag in
/// `two_sided` is 1 and either side may face the camera.
///
/// Candidates: the structure is thinned to one seed per `seed_spacing_m` cell; at
/// each seed with normal n, a camera is put at the viewing distance D (and each
/// further `distance_factors` × D) along n (and −n when two-sided), and along those
/// tilted up and down by each of `tilts_deg` and, where ±n is not near vertical, turned
/// left and right about z by each of `yaws_deg`, looking at the seed. A candidate is usable when it
/// is free (the caller's test: clear of every measured point by the UAV's clearance, in the free
/// space reachable from home), its pitch lies within the gimbal limits and the aiming line
/// of sight reaches its own seed (a seed whose normal points into a hollow is not aimed at
/// through the near wall); per seed and direction
/// only the nearest usable one is kept (a farther one stands in where the nearer are not free).
///
/// Scoring: what each candidate images of the structure points by the coverage
/// evaluator's rule (coverage_evaluator.h: in the image, range, GSD, incidence,
/// line of sight through the voxels).
///
/// Choice: greedy set cover (lazy gains, ties to the lower candidate index) until
/// `target_coverage` of the points some candidate images are imaged; then, in
/// reverse order of choice, every photo whose points are all imaged by another chosen
/// photo is removed. Deterministic for any thread count.
///
/// Multi-cover (`min_views` > 1, a reconstruction, issue 46): a point's level is the
/// number of chosen photos that image it with pairwise distinct rays, counted in order
/// of choice: a photo counts when its ray to the point (camera centre − point) differs
/// by ≥ `min_triangulation_deg` from every ray counted before, up to `min_views`. A
/// candidate's gain is the number of its points whose level it raises; the greedy stops
/// when `target_coverage` of the achievable levels (per point min(min_views, candidates
/// that image it)) are reached, then removes, latest first, every photo whose removal
/// lowers no point's level. A point at level min_views is imaged by min_views photos
/// whose rays differ pairwise by ≥ min_triangulation_deg (so its triangulation angle,
/// multi_view.h, is ≥ that). Gains only fall as photos are chosen, so lazy gains are exact.
///
/// `prefer_consistent`: a candidate's gain is weighted by 1 / (1 + t + y + f), t the index
/// of its tilt (0 along ±n, 1 for tilts_deg[0], ...), y of its yaw (the same for yaws_deg)
/// and f of its distance factor, so tilted, turned and farther photos are chosen only for what the
/// level, near ones do not image well: neighbouring photos then share range and tilt, which feature
/// matching needs.
///
/// `link_share` > 0 (a reconstruction): the chosen photos are registered as an
/// incremental reconstruction (COLMAP's mapper) would: a model starts from the pair
/// sharing the most points (≥ link_share × the smaller set, optical axes within
/// `link_max_angle_deg`, what feature matching can join), and a photo joins it once
/// ≥ link_share of its points are each imaged by two photos of the model whose axes are
/// within link_max_angle_deg of its own (points it can match that are already
/// triangulated); the rest start further models. A link by shared points alone is not
/// enough: across a corner, the far face's photos need two photos of the model that see
/// it. While more than one model is left, the candidate that registers in the largest and
/// images the most points seen outside it and not yet twice in it is added (ties to the
/// lower index). `components` reports the models left (1: one model).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "uavip/core/types.h"
#include "uavip/coverage/coverage_evaluator.h"
#include "uavip/coverage/flight_strategy.h"

namespace uavip::coverage {

/// Options of the view selection.
struct StructureViewOptions {
  double standoff_m{0.0};               ///< viewing distance D from a seed [m] (> 0)
  std::vector<double> tilts_deg{35.0};  ///< extra tilts of ±n up and down [deg], each in (0, 90)
  /// Extra turns of a not-vertical ±n about z, left and right [deg], each in (0, 90):
  /// corner photos that see both faces of a vertical edge (a reconstruction's links).
  std::vector<double> yaws_deg;
  /// Candidates at these multiples of standoff_m, each ≥ 1, nearest first (a farther
  /// one is kept only where the nearer ones are not free: a pocket, a measured outlier).
  std::vector<double> distance_factors{1.0};
  double seed_spacing_m{0.0};         ///< seed cell edge [m]; 0 = D / 3
  double target_coverage{0.99};       ///< of the imageable points, in (0, 1]
  GimbalLimits gimbal;                ///< a candidate's pitch must lie within
  CoverageCriteria criteria;          ///< what "imaged" means
  int threads{2};                     ///< workers for scoring
  int min_views{1};                   ///< photos with distinct rays asked of every point (≥ 1)
  double min_triangulation_deg{0.0};  ///< least angle between two counted rays [deg]
  bool prefer_consistent{false};      ///< weight gains toward untilted, near candidates
  double link_share{0.0};             ///< 0 = no linking; else in (0, 1]
  double link_max_angle_deg{50.0};    ///< linked photos' optical axes differ by ≤ this [deg]

  /// Throws InputError naming the bad field (prefix `where`).
  void validate(const std::string& where = "structure_views") const;
};

/// True when a camera may stand at this point [m].
using ViewpointFree = std::function<bool(const Vec3&)>;

/// The chosen photos and what they image.
struct StructureViews {
  std::vector<ViewPose> views;     ///< in order of choice
  std::vector<Vec3> targets;       ///< the seed each view looks at [m]
  std::size_t seeds{0};            ///< seed points
  std::size_t candidates{0};       ///< candidate poses made
  std::size_t free_candidates{0};  ///< kept: per seed and direction the nearest usable one
  std::size_t points{0};           ///< structure points
  std::size_t imageable{0};        ///< points some free candidate images
  std::size_t covered{0};          ///< points the chosen views image
  /// Per chosen view, the points it images (ascending indices into the points).
  std::vector<std::vector<std::uint32_t>> imaged;
  std::size_t achievable{0};  ///< Σ over points of min(min_views, candidates imaging it)
  std::size_t reached{0};     ///< Σ over points of the chosen views' level (≤ achievable)
  std::size_t linking{0};     ///< photos added to join the models (link_share > 0)
  std::size_t components{0};  ///< models the chosen photos register in (link_share > 0)
};

/// Share of what two views image in common: |a ∩ b| / max(|a|, |b|) (0 when both are
/// empty); `a` and `b` ascending.
double imagedShare(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b);

/// Selects the photos of a structure (see the file comment). `normals` holds one
/// normal per point, `two_sided` one flag per point or nothing (every normal
/// one-sided). `los` decides what a candidate images; `aim_los` (nullptr: `los`)
/// whether it sees its own seed: a closed wall there (VoxelLineOfSight's point extent)
/// keeps a sparse cloud's gaps from passing a camera that looks through the near face.
/// Throws InputError for invalid options, a normal or flag count other than
/// points.size(), or non-finite input.
StructureViews selectStructureViews(const PointList& points, const std::vector<Vec3>& normals,
                                    const std::vector<char>& two_sided, const CameraModel& camera,
                                    const LineOfSight* los, const ViewpointFree& is_free,
                                    const StructureViewOptions& options,
                                    const LineOfSight* aim_los = nullptr);

/// The pose at `position` looking at `target`: yaw = atan2 of the horizontal
/// direction (0 when looking straight up or down), pitch = its elevation [deg].
ViewPose lookAt(const Vec3& position, const Vec3& target);

}  // namespace uavip::coverage
