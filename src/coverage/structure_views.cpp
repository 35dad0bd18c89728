#include "uavip/coverage/structure_views.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <queue>
#include <utility>

#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/voxel_key.h"

namespace uavip::coverage {

namespace {

/// A candidate pose, the seed it looks at, and its direction: the candidates of one
/// seed and direction (one per distance factor, nearest first) share `direction`.
struct Candidate {
  ViewPose pose;
  Vec3 target;
  std::size_t direction{0};
  int tilt{0};    ///< 0 along ±n, k for tilts_deg[k − 1]
  int yaw{0};     ///< 0 along ±n, k for yaws_deg[k − 1]
  int factor{0};  ///< index into distance_factors
};

/// A viewing direction (from the seed toward the camera) and which tilt or yaw made it.
struct Direction {
  Vec3 d;
  int tilt{0};
  int yaw{0};
};

/// Viewing directions at a seed with normal n: n (and −n when two-sided), each also
/// tilted toward +z and −z by each tilt (about the horizontal axis n × z; about x when
/// n is vertical) and, when ±n is not near vertical, turned left and right about z by
/// each yaw (the corner photos that see two faces of an edge at once).
std::vector<Direction> viewingDirections(const Vec3& n, bool two_sided,
                                         const std::vector<double>& tilts_deg,
                                         const std::vector<double>& yaws_deg) {
  Vec3 up = Vec3::UnitZ() - n.z() * n;  // the part of +z across n
  if (up.norm() < 1e-6) up = Vec3::UnitX() - n.x() * n;
  up.normalize();
  std::vector<Direction> dirs;
  for (const double sign : {1.0, -1.0}) {
    if (sign < 0.0 && !two_sided) break;
    const Vec3 m = sign * n;
    dirs.push_back({m, 0, 0});
    for (std::size_t k = 0; k < tilts_deg.size(); ++k) {
      const double t = tilts_deg[k] * kDegToRad;
      const int index = static_cast<int>(k) + 1;
      dirs.push_back({(std::cos(t) * m + std::sin(t) * up).normalized(), index, 0});
      dirs.push_back({(std::cos(t) * m - std::sin(t) * up).normalized(), index, 0});
    }
    // A yaw turns the horizontal part of m about z; a near-vertical m has none to turn.
    const double horizontal = std::hypot(m.x(), m.y());
    if (horizontal < 0.5) continue;
    for (std::size_t k = 0; k < yaws_deg.size(); ++k) {
      const int index = static_cast<int>(k) + 1;
      for (const double turn : {1.0, -1.0}) {
        const double a = turn * yaws_deg[k] * kDegToRad;
        const Vec3 r(std::cos(a) * m.x() - std::sin(a) * m.y(),
                     std::sin(a) * m.x() + std::cos(a) * m.y(), m.z());
        dirs.push_back({r.normalized(), 0, index});
      }
    }
  }
  return dirs;
}

/// Seeds: one point per seed cell (the centroid of the cell's points), with the
/// normal of the structure point nearest to it.
std::vector<Candidate> makeCandidates(const PointList& points, const std::vector<Vec3>& normals,
                                      const std::vector<char>& two_sided,
                                      const StructureViewOptions& o, std::size_t& seeds) {
  const double spacing = o.seed_spacing_m > 0.0 ? o.seed_spacing_m : o.standoff_m / 3.0;
  const VoxelKeyer keyer = VoxelKeyer::forPoints(points, spacing, "structure seed spacing");
  // Per cell, the point nearest to the cell's centroid stands for it (its own normal).
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    keyed[i] = {keyer.key(points[i]), static_cast<std::uint32_t>(i)};
  std::sort(keyed.begin(), keyed.end());
  std::vector<Candidate> out;
  seeds = 0;
  std::size_t directions = 0;
  for (std::size_t b = 0; b < keyed.size();) {
    std::size_t e = b;
    Vec3 sum = Vec3::Zero();
    for (; e < keyed.size() && keyed[e].first == keyed[b].first; ++e)
      sum += points[keyed[e].second];
    const Vec3 centroid = sum / static_cast<double>(e - b);
    std::uint32_t best = keyed[b].second;
    for (std::size_t j = b; j < e; ++j) {
      if ((points[keyed[j].second] - centroid).squaredNorm() <
          (points[best] - centroid).squaredNorm())
        best = keyed[j].second;
    }
    ++seeds;
    const Vec3& p = points[best];
    const bool both = !two_sided.empty() && two_sided[best] != 0;
    for (const Direction& dir : viewingDirections(normals[best], both, o.tilts_deg, o.yaws_deg)) {
      for (std::size_t f = 0; f < o.distance_factors.size(); ++f) {
        const Vec3 c = p + o.distance_factors[f] * o.standoff_m * dir.d;
        out.push_back({lookAt(c, p), p, directions, dir.tilt, dir.yaw, static_cast<int>(f)});
      }
      ++directions;
    }
    b = e;
  }
  return out;
}

/// Lazy greedy set cover: photos in order of choice until `needed` points are covered.
std::vector<std::size_t> greedyCover(const std::vector<std::vector<std::uint32_t>>& sets,
                                     std::size_t n_points, std::size_t needed,
                                     std::vector<int>& count) {
  std::vector<char> covered(n_points, 0);
  count.assign(n_points, 0);
  // Max-heap on (gain, −index): equal gains go to the lower index.
  std::priority_queue<std::pair<std::size_t, std::int64_t>> heap;
  for (std::size_t i = 0; i < sets.size(); ++i)
    if (!sets[i].empty()) heap.push({sets[i].size(), -static_cast<std::int64_t>(i)});
  std::vector<std::size_t> chosen;
  std::size_t done = 0;
  while (done < needed && !heap.empty()) {
    const auto [stale_gain, neg] = heap.top();
    heap.pop();
    const auto i = static_cast<std::size_t>(-neg);
    std::size_t gain = 0;
    for (const auto p : sets[i]) gain += covered[p] == 0;
    if (gain == 0) continue;
    if (!heap.empty() && gain < heap.top().first) {  // stale: push back with its true gain
      heap.push({gain, neg});
      continue;
    }
    chosen.push_back(i);
    for (const auto p : sets[i]) {
      done += covered[p] == 0;
      covered[p] = 1;
      ++count[p];
    }
  }
  return chosen;
}

/// Removes, latest first, every chosen photo whose points all have another photo.
std::vector<std::size_t> pruneRedundant(const std::vector<std::vector<std::uint32_t>>& sets,
                                        const std::vector<std::size_t>& chosen,
                                        std::vector<int>& count) {
  std::vector<char> keep(chosen.size(), 1);
  for (std::size_t k = chosen.size(); k-- > 0;) {
    const auto& s = sets[chosen[k]];
    if (std::all_of(s.begin(), s.end(), [&](std::uint32_t p) { return count[p] >= 2; })) {
      keep[k] = 0;
      for (const auto p : s) --count[p];
    }
  }
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < chosen.size(); ++k)
    if (keep[k]) out.push_back(chosen[k]);
  return out;
}

/// The multi-cover of the file comment: per point the rays counted so far.
class MultiCover {
 public:
  MultiCover(const PointList& points, const std::vector<Vec3>& centres, int min_views,
             double min_angle_deg)
      : points_(points),
        centres_(centres),
        m_(static_cast<std::size_t>(min_views)),
        max_cos_(std::cos(min_angle_deg * kDegToRad)),
        level_(points.size(), 0),
        rays_(points.size() * m_) {}

  /// True when view v's ray to point p differs enough from p's counted rays and p's
  /// level is below min_views.
  [[nodiscard]] bool raises(std::size_t v, std::uint32_t p) const {
    if (level_[p] >= m_) return false;
    const Vec3 ray = (centres_[v] - points_[p]).normalized();
    for (std::size_t k = 0; k < level_[p]; ++k)
      if (ray.dot(rays_[p * m_ + k]) > max_cos_) return false;
    return true;
  }
  std::size_t gain(std::size_t v, const std::vector<std::uint32_t>& set) const {
    std::size_t g = 0;
    for (const auto p : set) g += raises(v, p) ? 1 : 0;
    return g;
  }
  /// Counts view v at its points; returns the levels raised.
  std::size_t add(std::size_t v, const std::vector<std::uint32_t>& set) {
    std::size_t g = 0;
    for (const auto p : set) {
      if (!raises(v, p)) continue;
      rays_[p * m_ + level_[p]] = (centres_[v] - points_[p]).normalized();
      ++level_[p];
      ++g;
    }
    return g;
  }
  void reset() { std::fill(level_.begin(), level_.end(), 0); }
  [[nodiscard]] std::size_t level(std::uint32_t p) const { return level_[p]; }

 private:
  const PointList& points_;
  const std::vector<Vec3>& centres_;
  std::size_t m_;
  double max_cos_;
  std::vector<std::size_t> level_;
  std::vector<Vec3> rays_;
};

/// Lazy greedy multi-cover with weighted gains (file comment): photos in order of
/// choice until `needed` levels are reached or no candidate raises one.
std::vector<std::size_t> greedyMultiCover(const std::vector<std::vector<std::uint32_t>>& sets,
                                          const std::vector<double>& weights, MultiCover& cover,
                                          std::size_t needed) {
  // Max-heap on (weighted gain, −index): equal keys go to the lower index.
  std::priority_queue<std::pair<double, std::int64_t>> heap;
  for (std::size_t i = 0; i < sets.size(); ++i)
    if (!sets[i].empty())
      heap.push({weights[i] * static_cast<double>(sets[i].size()), -static_cast<std::int64_t>(i)});
  std::vector<std::size_t> chosen;
  std::size_t done = 0;
  while (done < needed && !heap.empty()) {
    const auto [stale_key, neg] = heap.top();
    heap.pop();
    const auto i = static_cast<std::size_t>(-neg);
    const std::size_t gain = cover.gain(i, sets[i]);
    if (gain == 0) continue;
    const double key = weights[i] * static_cast<double>(gain);
    if (!heap.empty() && key < heap.top().first) {  // stale: push back with its true key
      heap.push({key, neg});
      continue;
    }
    chosen.push_back(i);
    done += cover.add(i, sets[i]);
  }
  return chosen;
}

/// Removes, latest first, every chosen photo whose removal lowers no point's level (the
/// levels recounted in order of choice without it).
std::vector<std::size_t> pruneMultiCover(const std::vector<std::vector<std::uint32_t>>& sets,
                                         const std::vector<std::size_t>& chosen,
                                         const PointList& points, const std::vector<Vec3>& centres,
                                         int min_views, double min_angle_deg) {
  const double max_cos = std::cos(min_angle_deg * kDegToRad);
  const auto m = static_cast<std::size_t>(min_views);
  // Per point the chosen photos (ranks in order of choice) that image it.
  std::vector<std::vector<std::uint32_t>> by_point(points.size());
  for (std::size_t k = 0; k < chosen.size(); ++k)
    for (const auto p : sets[chosen[k]]) by_point[p].push_back(static_cast<std::uint32_t>(k));
  std::vector<char> keep(chosen.size(), 1);
  // p's level by the kept photos other than rank `skip`, counted in order of choice.
  std::vector<Vec3> rays;
  const auto level = [&](std::uint32_t p, std::size_t skip) {
    rays.clear();
    for (const auto k : by_point[p]) {
      if (k == skip || keep[k] == 0) continue;
      const Vec3 ray = (centres[chosen[k]] - points[p]).normalized();
      if (std::all_of(rays.begin(), rays.end(),
                      [&](const Vec3& r) { return ray.dot(r) <= max_cos; }))
        rays.push_back(ray);
      if (rays.size() >= m) break;
    }
    return rays.size();
  };
  const std::size_t none = chosen.size();
  for (std::size_t k = chosen.size(); k-- > 0;) {
    const auto& s = sets[chosen[k]];
    if (std::all_of(s.begin(), s.end(),
                    [&](std::uint32_t p) { return level(p, k) >= level(p, none); }))
      keep[k] = 0;
  }
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < chosen.size(); ++k)
    if (keep[k]) out.push_back(chosen[k]);
  return out;
}

/// The chosen photos' registration as an incremental reconstruction builds it (file
/// comment, "Linking"): the photo ranks of each model, largest first.
class RegistrationModels {
 public:
  RegistrationModels(const std::vector<std::vector<std::uint32_t>>& sets,
                     const std::vector<Vec3>& axis, const std::vector<std::size_t>& chosen,
                     std::size_t n_points, double share, double min_cos)
      : sets_(sets),
        axis_(axis),
        chosen_(chosen),
        share_(share),
        min_cos_(min_cos),
        viewers_(n_points),
        model_(chosen.size(), -1) {
    for (std::size_t k = 0; k < chosen.size(); ++k)
      for (const auto p : sets[chosen[k]]) viewers_[p].push_back(static_cast<std::uint32_t>(k));
    while (true) {
      const auto [a, b] = seedPair();
      if (a == chosen.size()) break;
      grow(a, b);
    }
    for (std::size_t k = 0; k < chosen.size(); ++k)  // the unregistered: one model each
      if (model_[k] < 0) models_.push_back({k});
    std::stable_sort(models_.begin(), models_.end(),
                     [](const auto& x, const auto& y) { return x.size() > y.size(); });
  }

  const std::vector<std::vector<std::size_t>>& models() const { return models_; }

 private:
  bool compatible(std::size_t k, std::size_t l) const {
    return axis_[chosen_[k]].dot(axis_[chosen_[l]]) >= min_cos_;
  }
  /// Photo k has enough triangulated points to register.
  bool enough(std::size_t k, std::size_t anchored) const {
    return static_cast<double>(anchored) >= share_ * static_cast<double>(sets_[chosen_[k]].size());
  }

  /// The unregistered pair sharing the most points (≥ share of the smaller set, axes
  /// compatible); {n, n} when none is left.
  std::pair<std::size_t, std::size_t> seedPair() const {
    const std::size_t n = chosen_.size();
    std::pair<std::size_t, std::size_t> best{n, n};
    std::size_t best_common = 0;
    std::vector<std::size_t> common(n, 0);
    std::vector<std::size_t> touched;
    for (std::size_t a = 0; a < n; ++a) {
      if (model_[a] >= 0) continue;
      touched.clear();
      for (const auto p : sets_[chosen_[a]])
        for (const auto b : viewers_[p])
          if (b > a && model_[b] < 0 && common[b]++ == 0) touched.push_back(b);
      for (const auto b : touched) {
        const std::size_t smaller = std::min(sets_[chosen_[a]].size(), sets_[chosen_[b]].size());
        const bool better = common[b] > best_common ||
                            (common[b] == best_common && a == best.first && b < best.second);
        if (compatible(a, b) && better &&
            static_cast<double>(common[b]) >= share_ * static_cast<double>(smaller)) {
          best = {a, b};
          best_common = common[b];
        }
        common[b] = 0;
      }
    }
    return best;
  }

  /// One model from the seed pair: a photo registers once ≥ share of its points are each
  /// seen by two registered photos whose axes are compatible with its own.
  void grow(std::size_t a, std::size_t b) {
    const auto id = static_cast<int>(models_.size());
    models_.emplace_back();
    std::vector<std::vector<std::uint8_t>> seen_by(chosen_.size());
    std::vector<std::size_t> anchored(chosen_.size(), 0);
    std::vector<std::size_t> queue = {a, b};
    model_[a] = model_[b] = id;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::size_t k = queue[q];
      models_.back().push_back(k);
      for (const auto p : sets_[chosen_[k]]) {
        for (const auto j : viewers_[p]) {
          if (model_[j] >= 0 || !compatible(j, k)) continue;
          const auto& set = sets_[chosen_[j]];
          if (seen_by[j].empty()) seen_by[j].assign(set.size(), 0);
          const auto at =
              static_cast<std::size_t>(std::lower_bound(set.begin(), set.end(), p) - set.begin());
          if (seen_by[j][at] >= 2 || ++seen_by[j][at] != 2) continue;  // saturates at 2
          if (!enough(j, ++anchored[j])) continue;
          model_[j] = id;
          queue.push_back(j);
        }
      }
    }
  }

  const std::vector<std::vector<std::uint32_t>>& sets_;
  const std::vector<Vec3>& axis_;
  const std::vector<std::size_t>& chosen_;
  double share_;
  double min_cos_;
  std::vector<std::vector<std::uint32_t>> viewers_;  ///< per point, the ranks that image it
  std::vector<int> model_;                           ///< per rank, its model (−1: none yet)
  std::vector<std::vector<std::size_t>> models_;
};

/// The linking of the file comment: while the chosen photos register in more than one
/// model, adds the candidate that registers in the largest and brings it the most
/// points imaged outside it (not yet seen twice in it); returns the models left.
std::size_t linkModels(const std::vector<std::vector<std::uint32_t>>& sets,
                       const std::vector<Candidate>& usable, std::size_t n_points,
                       const StructureViewOptions& o, std::vector<std::size_t>& chosen,
                       std::size_t& added) {
  std::vector<Vec3> axis;
  axis.reserve(usable.size());
  for (const auto& c : usable) axis.push_back((c.target - c.pose.position).normalized());
  const double min_cos = std::cos(o.link_max_angle_deg * kDegToRad);
  std::vector<char> is_chosen(usable.size(), 0);
  for (const auto i : chosen) is_chosen[i] = 1;
  added = 0;
  while (true) {
    const RegistrationModels reg(sets, axis, chosen, n_points, o.link_share, min_cos);
    const auto& models = reg.models();
    if (models.size() <= 1) return models.size();
    std::vector<char> in_main(chosen.size(), 0);
    for (const auto k : models.front()) in_main[k] = 1;
    std::vector<std::vector<std::size_t>> main_by(n_points);  // chosen indices in the model
    std::vector<char> outside(n_points, 0);
    for (std::size_t k = 0; k < chosen.size(); ++k)
      for (const auto p : sets[chosen[k]]) {
        if (in_main[k] != 0)
          main_by[p].push_back(chosen[k]);
        else
          outside[p] = 1;
      }
    std::size_t best = usable.size(), best_gain = 0;
    for (std::size_t i = 0; i < usable.size(); ++i) {
      if (is_chosen[i] != 0 || sets[i].empty()) continue;
      std::size_t anchored = 0, gain = 0;
      for (const auto p : sets[i]) {
        std::size_t views = 0;
        for (const auto j : main_by[p]) views += axis[i].dot(axis[j]) >= min_cos ? 1 : 0;
        anchored += views >= 2 ? 1 : 0;
        gain += outside[p] != 0 && views < 2 ? 1 : 0;
      }
      if (gain > best_gain &&
          static_cast<double>(anchored) >= o.link_share * static_cast<double>(sets[i].size())) {
        best = i;
        best_gain = gain;
      }
    }
    if (best == usable.size()) return models.size();
    chosen.push_back(best);
    is_chosen[best] = 1;
    ++added;
  }
}

/// The multi-cover choice (file comment); fills out.achievable, reached and covered.
std::vector<std::size_t> chooseMultiCover(const PointList& points,
                                          const std::vector<Candidate>& usable,
                                          const std::vector<std::vector<std::uint32_t>>& sets,
                                          const StructureViewOptions& o, StructureViews& out) {
  std::vector<Vec3> centres;
  std::vector<double> weights;
  centres.reserve(usable.size());
  weights.reserve(usable.size());
  for (const auto& c : usable) {
    centres.push_back(c.pose.position);
    weights.push_back(o.prefer_consistent ? 1.0 / (1.0 + c.tilt + c.yaw + c.factor) : 1.0);
  }
  std::vector<std::size_t> candidates_of(points.size(), 0);
  for (const auto& s : sets)
    for (const auto p : s) ++candidates_of[p];
  const auto m = static_cast<std::size_t>(o.min_views);
  for (const auto n : candidates_of) out.achievable += std::min(m, n);
  const auto needed =
      static_cast<std::size_t>(std::ceil(o.target_coverage * static_cast<double>(out.achievable)));
  MultiCover cover(points, centres, o.min_views, o.min_triangulation_deg);
  std::vector<std::size_t> chosen =
      pruneMultiCover(sets, greedyMultiCover(sets, weights, cover, needed), points, centres,
                      o.min_views, o.min_triangulation_deg);
  if (o.link_share > 0.0)
    out.components = linkModels(sets, usable, points.size(), o, chosen, out.linking);
  cover.reset();
  for (const auto i : chosen) cover.add(i, sets[i]);
  for (std::uint32_t p = 0; p < points.size(); ++p) {
    out.reached += cover.level(p);
    out.covered += cover.level(p) > 0 ? 1 : 0;
  }
  return chosen;
}

}  // namespace

double imagedShare(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
  const std::size_t most = std::max(a.size(), b.size());
  if (most == 0) return 0.0;
  std::size_t common = 0;
  for (std::size_t i = 0, j = 0; i < a.size() && j < b.size();) {
    if (a[i] < b[j]) {
      ++i;
    } else if (b[j] < a[i]) {
      ++j;
    } else {
      ++common;
      ++i;
      ++j;
    }
  }
  return static_cast<double>(common) / static_cast<double>(most);
}

void StructureViewOptions::validate(const std::string& where) const {
  requireThat(std::isfinite(standoff_m) && standoff_m > 0.0, where, "standoff_m", "> 0 and finite",
              standoff_m);
  require(!distance_factors.empty(), where,
          "distance_factors: give at least one (1 = the standoff)");
  for (std::size_t i = 0; i < distance_factors.size(); ++i) {
    const double f = distance_factors[i];
    requireThat(std::isfinite(f) && f >= 1.0 && f <= 3.0, where, "distance_factors", "in [1, 3]",
                f);
    if (i > 0)
      requireThat(f > distance_factors[i - 1], where, "distance_factors",
                  "ascending (nearest first)", f);
  }
  for (const double t : tilts_deg)
    requireThat(std::isfinite(t) && t > 0.0 && t < 90.0, where, "tilts_deg", "in (0, 90)", t);
  for (const double y : yaws_deg)
    requireThat(std::isfinite(y) && y > 0.0 && y < 90.0, where, "yaws_deg", "in (0, 90)", y);
  requireThat(std::isfinite(seed_spacing_m) && seed_spacing_m >= 0.0, where, "seed_spacing_m",
              ">= 0 (0 = standoff / 3)", seed_spacing_m);
  requireThat(target_coverage > 0.0 && target_coverage <= 1.0, where, "target_coverage",
              "in (0, 1]", target_coverage);
  requireThat(threads >= 1, where, "threads", ">= 1", threads);
  requireThat(std::isfinite(link_share) && link_share >= 0.0 && link_share <= 1.0, where,
              "link_share", "in [0, 1]", link_share);
  requireThat(
      std::isfinite(link_max_angle_deg) && link_max_angle_deg > 0.0 && link_max_angle_deg <= 180.0,
      where, "link_max_angle_deg", "in (0, 180]", link_max_angle_deg);
  // The coverage table bounds the config's values; these guard a direct caller.
  requireThat(min_views >= 1 && min_views <= 64, where, "views per point", "in [1, 64]", min_views);
  requireThat(std::isfinite(min_triangulation_deg) && min_triangulation_deg >= 0.0 &&
                  min_triangulation_deg < 90.0,
              where, "triangulation angle [deg]", "in [0, 90)", min_triangulation_deg);
  criteria.validate(where + ".criteria");
}

ViewPose lookAt(const Vec3& position, const Vec3& target) {
  const Vec3 d = target - position;
  const double horizontal = std::hypot(d.x(), d.y());
  ViewPose pose;
  pose.position = position;
  pose.yaw_deg = horizontal > 1e-9 ? std::atan2(d.y(), d.x()) * kRadToDeg : 0.0;
  pose.pitch_deg = std::atan2(d.z(), horizontal) * kRadToDeg;
  return pose;
}

StructureViews selectStructureViews(const PointList& points, const std::vector<Vec3>& normals,
                                    const std::vector<char>& two_sided, const CameraModel& camera,
                                    const LineOfSight* los, const ViewpointFree& is_free,
                                    const StructureViewOptions& options,
                                    const LineOfSight* aim_los) {
  options.validate();
  require(normals.size() == points.size(), "structure_views",
          "one normal per point: " + std::to_string(points.size()) + " points, " +
              std::to_string(normals.size()) + " normals");
  require(two_sided.empty() || two_sided.size() == points.size(), "structure_views",
          "one two-sided flag per point or none: " + std::to_string(points.size()) + " points, " +
              std::to_string(two_sided.size()) + " flags");
  StructureViews out;
  out.points = points.size();
  if (points.empty()) return out;
  const std::vector<Candidate> all = makeCandidates(points, normals, two_sided, options, out.seeds);
  out.candidates = all.size();
  // Per seed and direction the nearest free candidate: a farther one stands in only
  // where the nearer ones are not free.
  const LineOfSight* aim = aim_los != nullptr ? aim_los : los;
  std::vector<Candidate> usable;
  for (const Candidate& c : all) {
    if (!usable.empty() && usable.back().direction == c.direction) continue;
    const double pitch = c.pose.pitch_deg;
    if (pitch < options.gimbal.pitch_min_deg || pitch > options.gimbal.pitch_max_deg) continue;
    if (is_free && !is_free(c.pose.position)) continue;
    // A camera that cannot see its own seed (a normal that points into a hollow) would
    // photograph whatever stands between, from far nearer than planned.
    if (aim != nullptr && !aim->clear(c.pose.position, c.target)) continue;
    usable.push_back(c);
  }
  out.free_candidates = usable.size();
  std::vector<ViewPose> poses;
  poses.reserve(usable.size());
  for (const auto& c : usable) poses.push_back(c.pose);
  const auto sets = imagedByView(points, normals, poses, camera, options.criteria, los,
                                 options.threads, two_sided.empty() ? nullptr : &two_sided);
  std::vector<char> seen(points.size(), 0);
  for (const auto& s : sets)
    for (const auto p : s) seen[p] = 1;
  for (const char s : seen) out.imageable += s != 0;
  std::vector<std::size_t> chosen;
  if (options.min_views == 1 && !options.prefer_consistent) {
    const auto needed = static_cast<std::size_t>(
        std::ceil(options.target_coverage * static_cast<double>(out.imageable)));
    std::vector<int> count;
    chosen = pruneRedundant(sets, greedyCover(sets, points.size(), needed, count), count);
    for (const int c : count) out.covered += c > 0;
    out.achievable = out.imageable;
    out.reached = out.covered;
  } else {
    chosen = chooseMultiCover(points, usable, sets, options, out);
  }
  for (const auto i : chosen) {
    out.views.push_back(usable[i].pose);
    out.targets.push_back(usable[i].target);
    out.imaged.push_back(sets[i]);
  }
  return out;
}

}  // namespace uavip::coverage
