#pragma once
/// \file
/// The image pairs worth matching (issue 46), written beside the photos as `pairs.txt`
/// (COLMAP's `matches_importer --match_type pairs`; docs/formats.md "The photo folder").
///
/// COLMAP's spatial matcher pairs each photo with the k nearest camera centres. An
/// edge link's photos (45° to both faces of a structure's edge, 0.15 m apart along it)
/// are each other's nearest, so they were matched only among themselves and one link
/// of the default scenario stayed out of the model (benchmarks/README.md, "Stop 61").
/// These pairs come from what the planned photos see instead: photo b's target (the
/// surface point at the centre of its image) projected into photo a lands (du, dv)
/// from a's image centre, a share (1 − |du|/W)(1 − |dv|/H) of a's image; zero behind
/// the camera, outside the image, or where the rays from the target to the two cameras
/// part by more than kPairMaxRayDeg (the target faces b: a sees it edge-on or from
/// behind). A pair scores the smaller of its two ways, and each photo is paired with
/// the kPairsPerPhoto others of the highest score.

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "uavip/photo/photo_folder.h"

namespace uavip::photo {

/// Photos each photo is paired with, at most (COLMAP's matchers' 10 neighbours).
constexpr int kPairsPerPhoto = 10;
/// Largest angle between the rays from a target to the two cameras of a pair [deg]:
/// the coverage's 75° incidence limit less a margin for SIFT across viewpoints.
constexpr double kPairMaxRayDeg = 60.0;

/// Share of photo a's image about the point where photo b's target lands, in [0, 1]
/// (see the file comment); 1 at a's image centre.
double targetShare(const coverage::PinholeIntrinsics& k, const PlannedPhoto& a,
                   const PlannedPhoto& b);

/// The pairs (i < j, indices into `photos`), ascending: every photo with the
/// `per_photo` others of the highest min(targetShare(i, j), targetShare(j, i)) > 0,
/// ties in flown order. On every core; the same pairs whatever the thread count.
std::vector<std::pair<std::size_t, std::size_t>> viewPairs(const std::vector<PlannedPhoto>& photos,
                                                           const PhotoCamera& camera,
                                                           int per_photo = kPairsPerPhoto,
                                                           int threads = 1);

/// pairs.txt: one pair a line, "<stop_id>.png <stop_id>.png".
std::string colmapPairs(const std::vector<PlannedPhoto>& photos,
                        const std::vector<std::pair<std::size_t, std::size_t>>& pairs);

}  // namespace uavip::photo
