#include "uavip/planning/tour.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/parallel.h"

namespace uavip::planning {

namespace {

/// Slot, cluster and point numbers are ints; this is their vector index.
constexpr std::size_t index(int number) { return static_cast<std::size_t>(number); }

/// Cache mark of a pair not evaluated yet (checkedCost never returns NaN).
constexpr double kNotEvaluated = std::numeric_limits<double>::quiet_NaN();
/// Largest Held–Karp instance: 2^16 subsets × ΣV slots of a double and an int each.
constexpr int kMaxExactClusters = 16;
/// A local-search move must gain more than this fraction of the tour cost, so that
/// rounding differences between partial and full evaluations cannot make it cycle.
constexpr double kMinRelativeGain = 1e-10;
/// Longest run of consecutive clusters an Or-opt move relocates.
constexpr int kMaxOrOptLength = 3;

void checkClusters(const std::vector<TourCluster>& clusters) {
  if (clusters.empty()) throw std::invalid_argument("tour: no cluster (cluster 0 must be home)");
  if (clusters[0].variants.size() != 1)
    throw std::invalid_argument("tour: home (cluster 0) must have exactly one variant");
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    if (clusters[c].variants.empty())
      throw std::invalid_argument("tour: cluster " + std::to_string(c) + " has no variant");
    for (const auto& v : clusters[c].variants)
      if (!(v.inner >= 0.0))
        throw std::invalid_argument("tour: cluster " + std::to_string(c) +
                                    " has a negative or NaN inner cost");
  }
}

/// Throws unless `order` visits every non-home cluster exactly once.
void checkOrder(const std::vector<TourCluster>& clusters, const std::vector<int>& order) {
  const int n = static_cast<int>(clusters.size());
  if (static_cast<int>(order.size()) != n - 1)
    throw std::invalid_argument("tour: the order must list each of the " + std::to_string(n - 1) +
                                " non-home clusters once");
  std::vector<bool> seen(clusters.size(), false);
  for (const int c : order) {
    if (c < 1 || c >= n || seen[index(c)])
      throw std::invalid_argument("tour: cluster " + std::to_string(c) +
                                  " in the order is home, unknown or repeated");
    seen[index(c)] = true;
  }
}

/// Throws unless `tour` is a valid order with one valid variant per visited cluster.
void checkTour(const std::vector<TourCluster>& clusters, const Tour& tour) {
  checkOrder(clusters, tour.order);
  if (tour.variant.size() != tour.order.size())
    throw std::invalid_argument("tour: one variant per visited cluster is needed");
  for (std::size_t i = 0; i < tour.order.size(); ++i) {
    const auto& variants = clusters[index(tour.order[i])].variants;
    if (tour.variant[i] < 0 || tour.variant[i] >= static_cast<int>(variants.size()))
      throw std::invalid_argument("tour: variant " + std::to_string(tour.variant[i]) +
                                  " of cluster " + std::to_string(tour.order[i]) +
                                  " does not exist");
  }
}

/// The callback's value, checked: non-negative (+inf allowed), not NaN.
double checkedCost(const PointCost& cost, int from_point, int to_point) {
  const double value = cost(from_point, to_point);
  if (!(value >= 0.0))
    throw std::invalid_argument("tour: cost(" + std::to_string(from_point) + ", " +
                                std::to_string(to_point) + ") is negative or NaN");
  return value;
}

/// The clusters flattened into slots, one per cluster variant (slot 0 is home), and
/// the callback behind a cache: each (from, to) pair of point ids is evaluated once.
class TourModel {
 public:
  TourModel(const std::vector<TourCluster>& clusters, const PointCost& cost) : cost_(cost) {
    std::unordered_map<int, int> dense_of_id;
    auto dense = [&](int id) {
      const auto [it, added] = dense_of_id.emplace(id, static_cast<int>(point_ids_.size()));
      if (added) point_ids_.push_back(id);
      return it->second;
    };
    first_slot_.push_back(0);
    endpoints_.resize(clusters.size());
    for (std::size_t c = 0; c < clusters.size(); ++c) {
      for (const auto& v : clusters[c].variants) {
        cluster_of_slot_.push_back(static_cast<int>(c));
        entry_.push_back(dense(v.entry));
        exit_.push_back(dense(v.exit));
        inner_.push_back(c == 0 ? 0.0 : v.inner);  // home's inner cost is never counted
        endpoints_[c].push_back(entry_.back());
        endpoints_[c].push_back(exit_.back());
      }
      first_slot_.push_back(static_cast<int>(cluster_of_slot_.size()));
      std::sort(endpoints_[c].begin(), endpoints_[c].end());
      endpoints_[c].erase(std::unique(endpoints_[c].begin(), endpoints_[c].end()),
                          endpoints_[c].end());
    }
    const std::size_t points = point_ids_.size();
    cached_.assign(points * points, kNotEvaluated);
  }

  int clusterCount() const { return static_cast<int>(first_slot_.size()) - 1; }
  int slotCount() const { return first_slot_.back(); }
  /// Slots of `cluster` are [firstSlot(cluster), endSlot(cluster)).
  int firstSlot(int cluster) const { return first_slot_[index(cluster)]; }
  int endSlot(int cluster) const { return first_slot_[index(cluster) + 1]; }
  int clusterOf(int slot) const { return cluster_of_slot_[index(slot)]; }
  int variantOf(int slot) const { return slot - firstSlot(clusterOf(slot)); }
  /// Cost flown inside the slot's cluster in its variant [m]; 0 for home.
  double inner(int slot) const { return inner_[index(slot)]; }
  /// Cost from leaving `from_slot` (its exit) to entering `to_slot` (its entry) [m].
  double leg(int from_slot, int to_slot) {
    return pointCost(exit_[index(from_slot)], entry_[index(to_slot)]);
  }
  /// Dense indices of every entry and exit point of any variant of `cluster`.
  const std::vector<int>& endpoints(int cluster) const { return endpoints_[index(cluster)]; }
  /// Cached callback between dense point indices [m].
  double pointCost(int from, int to) {
    const std::size_t at = index(from) * point_ids_.size() + index(to);
    double& value = cached_[at];
    if (std::isnan(value))
      value = checkedCost(cost_, point_ids_[index(from)], point_ids_[index(to)]);
    return value;
  }

 private:
  const PointCost& cost_;
  std::vector<int> point_ids_;   ///< callback id of each dense point index
  std::vector<int> first_slot_;  ///< per cluster, plus one past the last slot
  std::vector<int> cluster_of_slot_;
  std::vector<int> entry_, exit_;  ///< dense point index per slot
  std::vector<double> inner_;      ///< per slot [m]
  std::vector<std::vector<int>> endpoints_;
  std::vector<double> cached_;  ///< point × point [m]; kNotEvaluated until asked
};

/// Index of the smallest value; the first on ties, so +inf everywhere still picks one.
template <typename ValueOf>
int argMin(int begin, int end, ValueOf value_of, double* best) {
  int arg = -1;
  for (int i = begin; i < end; ++i) {
    const double value = value_of(i);
    if (arg < 0 || value < *best) {
      arg = i;
      *best = value;
    }
  }
  return arg;
}

/// bestVariants on a checked order: DP over positions × variants, with predecessors.
Tour optimiseVariants(TourModel& model, const std::vector<int>& order) {
  Tour tour;
  tour.order = order;
  tour.exact = order.size() <= 1;
  if (order.empty()) return tour;
  // head[s]: least cost from take-off to leaving slot s's cluster in that variant.
  std::vector<double> head(index(model.slotCount()), kInf);
  std::vector<int> previous(head.size(), -1);
  head[0] = 0.0;
  int before = 0;
  for (const int cluster : order) {
    for (int s = model.firstSlot(cluster); s < model.endSlot(cluster); ++s) {
      double best = kInf;
      previous[index(s)] = argMin(
          model.firstSlot(before), model.endSlot(before),
          [&](int p) { return head[index(p)] + model.leg(p, s); }, &best);
      head[index(s)] = best + model.inner(s);
    }
    before = cluster;
  }
  int slot = argMin(
      model.firstSlot(before), model.endSlot(before),
      [&](int s) { return head[index(s)] + model.leg(s, 0); }, &tour.cost);
  tour.variant.resize(order.size());
  for (std::size_t i = order.size(); i-- > 0;) {
    tour.variant[i] = model.variantOf(slot);
    slot = previous[index(slot)];
  }
  return tour;
}

/// Held–Karp over (visited subset, last slot); slot s ≥ 1 is column s − 1.
Tour heldKarp(TourModel& model) {
  const int clusters = model.clusterCount() - 1;
  const int columns = model.slotCount() - 1;
  const std::uint32_t full = (std::uint32_t{1} << clusters) - 1;
  const auto bit = [](int cluster) { return std::uint32_t{1} << (cluster - 1); };
  const auto at = [&](std::uint32_t subset, int slot) {
    return std::size_t{subset} * index(columns) + index(slot - 1);
  };
  constexpr int kUnreached = -1;
  constexpr int kFromHome = 0;
  // best: least cost from take-off through the subset, ending by leaving the slot.
  std::vector<double> best((std::size_t{full} + 1) * index(columns), kInf);
  std::vector<int> previous(best.size(), kUnreached);
  for (int s = 1; s <= columns; ++s) {
    best[at(bit(model.clusterOf(s)), s)] = model.leg(0, s) + model.inner(s);
    previous[at(bit(model.clusterOf(s)), s)] = kFromHome;
  }
  for (std::uint32_t subset = 1; subset < full; ++subset) {
    for (int s = 1; s <= columns; ++s) {
      const std::size_t from = at(subset, s);
      if (previous[from] == kUnreached) continue;
      for (int next = 1; next <= clusters; ++next) {
        if (subset & bit(next)) continue;
        const std::uint32_t grown = subset | bit(next);
        for (int t = model.firstSlot(next); t < model.endSlot(next); ++t) {
          const double value = best[from] + model.leg(s, t) + model.inner(t);
          const std::size_t to = at(grown, t);
          if (previous[to] == kUnreached || value < best[to]) {
            best[to] = value;
            previous[to] = s;
          }
        }
      }
    }
  }
  Tour tour;
  tour.exact = true;
  int slot = argMin(
      1, columns + 1, [&](int s) { return best[at(full, s)] + model.leg(s, 0); }, &tour.cost);
  std::uint32_t subset = full;
  while (slot != kFromHome) {
    tour.order.push_back(model.clusterOf(slot));
    tour.variant.push_back(model.variantOf(slot));
    const int before = previous[at(subset, slot)];
    subset &= ~bit(model.clusterOf(slot));
    slot = before;
  }
  std::reverse(tour.order.begin(), tour.order.end());
  std::reverse(tour.variant.begin(), tour.variant.end());
  return tour;
}

/// From home, repeatedly the unvisited cluster with the cheapest leg to any of its
/// variants' entries (lowest index on ties), leaving it by that variant's exit.
std::vector<int> nearestNeighbourOrder(TourModel& model) {
  const int clusters = model.clusterCount();
  std::vector<bool> visited(index(clusters), false);
  std::vector<int> order;
  int at_slot = 0;
  for (int step = 1; step < clusters; ++step) {
    double best = kInf;
    int best_slot = -1;
    for (int c = 1; c < clusters; ++c) {
      if (visited[index(c)]) continue;
      for (int s = model.firstSlot(c); s < model.endSlot(c); ++s) {
        const double value = model.leg(at_slot, s);
        if (best_slot < 0 || value < best) {
          best = value;
          best_slot = s;
        }
      }
    }
    const int chosen = model.clusterOf(best_slot);
    visited[index(chosen)] = true;
    order.push_back(chosen);
    at_slot = best_slot;
  }
  return order;
}

/// Clusters 1..n−1 by index.
std::vector<int> indexOrder(const TourModel& model) {
  std::vector<int> order(index(model.clusterCount() - 1));
  std::iota(order.begin(), order.end(), 1);
  return order;
}

/// First-improvement local search over the order; a candidate order is always costed
/// with its best variants. Keeps, per slot of the current order, the best cost of the
/// prefix ending there and of the suffix starting there, so a move that rewrites the
/// positions lo..hi is costed in O((hi − lo + 1)·V²).
class OrderSearch {
 public:
  OrderSearch(TourModel& model, std::vector<int> order)
      : model_(model),
        order_(std::move(order)),
        head_(index(model.slotCount()), kInf),
        tail_(head_.size(), kInf) {
    int most_variants = 1;
    for (int c = 0; c < model.clusterCount(); ++c)
      most_variants = std::max(most_variants, model.endSlot(c) - model.firstSlot(c));
    current_.resize(index(most_variants));
    next_.resize(current_.size());
    refresh();
  }

  const std::vector<int>& order() const { return order_; }

  /// Every 2-opt, then every Or-opt move once, applying each that gains. True if any did.
  bool improvePass() {
    const bool reversed = twoOptPass();
    const bool moved = orOptPass();
    return reversed || moved;
  }

 private:
  int size() const { return static_cast<int>(order_.size()); }
  double& head(int slot) { return head_[index(slot)]; }
  double& tail(int slot) { return tail_[index(slot)]; }

  /// Recomputes head_, tail_ and cost_ for order_.
  void refresh() {
    head(0) = 0.0;  // take-off
    tail(0) = 0.0;  // landing
    int before = 0;
    for (const int cluster : order_) {
      for (int s = model_.firstSlot(cluster); s < model_.endSlot(cluster); ++s) {
        double best = kInf;
        argMin(
            model_.firstSlot(before), model_.endSlot(before),
            [&](int p) { return head(p) + model_.leg(p, s); }, &best);
        head(s) = best + model_.inner(s);
      }
      before = cluster;
    }
    int after = 0;
    for (auto it = order_.rbegin(); it != order_.rend(); ++it) {
      for (int s = model_.firstSlot(*it); s < model_.endSlot(*it); ++s) {
        double best = kInf;
        argMin(
            model_.firstSlot(after), model_.endSlot(after),
            [&](int t) { return model_.leg(s, t) + tail(t); }, &best);
        tail(s) = model_.inner(s) + best;
      }
      after = *it;
    }
    cost_ = tail(0);  // only when the order is empty
    if (!order_.empty()) {
      cost_ = kInf;
      argMin(
          model_.firstSlot(after), model_.endSlot(after),
          [&](int s) { return model_.leg(0, s) + tail(s); }, &cost_);
    }
  }

  /// Tour cost with positions lo..hi replaced by window_ (same length).
  double windowCost(int lo, int hi) {
    const int before = lo > 0 ? order_[index(lo - 1)] : 0;
    const int after = hi + 1 < size() ? order_[index(hi + 1)] : 0;
    int last = before;
    for (int s = model_.firstSlot(before); s < model_.endSlot(before); ++s)
      current_[index(s - model_.firstSlot(before))] = head(s);
    for (const int cluster : window_) {
      for (int s = model_.firstSlot(cluster); s < model_.endSlot(cluster); ++s) {
        double best = kInf;
        argMin(
            model_.firstSlot(last), model_.endSlot(last),
            [&](int p) { return current_[index(p - model_.firstSlot(last))] + model_.leg(p, s); },
            &best);
        next_[index(s - model_.firstSlot(cluster))] = best + model_.inner(s);
      }
      std::swap(current_, next_);
      last = cluster;
    }
    double total = kInf;
    for (int s = model_.firstSlot(last); s < model_.endSlot(last); ++s)
      for (int t = model_.firstSlot(after); t < model_.endSlot(after); ++t)
        total = std::min(total,
                         current_[index(s - model_.firstSlot(last))] + model_.leg(s, t) + tail(t));
    return total;
  }

  /// Applies window_ at positions lo..hi if that makes the tour cheaper.
  bool tryWindow(int lo, int hi) {
    const double candidate = windowCost(lo, hi);
    if (!(candidate < cost_ - kMinRelativeGain * std::max(1.0, cost_))) return false;
    std::copy(window_.begin(), window_.end(), order_.begin() + lo);
    refresh();
    return true;
  }

  /// Reverses every segment i..j (its clusters then flown the other way round).
  bool twoOptPass() {
    bool improved = false;
    for (int i = 0; i + 1 < size(); ++i) {
      for (int j = i + 1; j < size(); ++j) {
        window_.assign(order_.rbegin() + (size() - 1 - j), order_.rbegin() + (size() - i));
        improved = tryWindow(i, j) || improved;
      }
    }
    return improved;
  }

  /// Moves every run of 1..kMaxOrOptLength clusters, kept or reversed, so that it
  /// starts at every other position.
  bool orOptPass() {
    bool improved = false;
    for (int length = 1; length <= kMaxOrOptLength && length < size(); ++length) {
      for (int i = 0; i + length <= size(); ++i) {
        for (int start = 0; start + length <= size(); ++start) {
          if (start == i) continue;
          for (const bool reverse : {false, true}) {
            if (reverse && length == 1) continue;
            improved = tryRelocation(i, length, start, reverse) || improved;
          }
        }
      }
    }
    return improved;
  }

  /// Or-opt: the run at i..i+length−1 moved to start at `start`.
  bool tryRelocation(int i, int length, int start, bool reverse) {
    const auto run_begin = order_.begin() + i;
    const auto run_end = run_begin + length;
    window_.clear();
    if (start < i) {  // run first, then the clusters it jumps over
      window_.insert(window_.end(), run_begin, run_end);
      if (reverse) std::reverse(window_.begin(), window_.end());
      window_.insert(window_.end(), order_.begin() + start, run_begin);
      return tryWindow(start, i + length - 1);
    }
    window_.insert(window_.end(), run_end, order_.begin() + start + length);
    const auto run_at = window_.insert(window_.end(), run_begin, run_end);
    if (reverse) std::reverse(run_at, window_.end());
    return tryWindow(i, start + length - 1);
  }

  TourModel& model_;
  std::vector<int> order_;
  std::vector<double> head_;  ///< per slot: take-off to leaving its cluster in that variant [m]
  std::vector<double> tail_;  ///< per slot: entering its cluster in that variant to landing [m]
  double cost_{kInf};
  std::vector<int> window_;             ///< candidate clusters for positions lo..hi
  std::vector<double> current_, next_;  ///< window DP, per variant [m]
};

Tour heuristic(TourModel& model, const TourOptions& options) {
  std::vector<int> start = nearestNeighbourOrder(model);
  std::vector<int> naive = indexOrder(model);
  if (optimiseVariants(model, naive).cost < optimiseVariants(model, start).cost)
    start = std::move(naive);
  OrderSearch search(model, std::move(start));
  for (int pass = 0; pass < options.max_passes; ++pass)
    if (!search.improvePass()) break;
  return optimiseVariants(model, search.order());
}

}  // namespace

double tourCost(const std::vector<TourCluster>& clusters, const Tour& tour, const PointCost& cost) {
  checkClusters(clusters);
  checkTour(clusters, tour);
  if (tour.order.empty()) return 0.0;
  const auto& home = clusters[0].variants[0];
  double total = 0.0;
  int at_point = home.exit;
  for (std::size_t i = 0; i < tour.order.size(); ++i) {
    const auto& v = clusters[index(tour.order[i])].variants[index(tour.variant[i])];
    total += checkedCost(cost, at_point, v.entry) + v.inner;
    at_point = v.exit;
  }
  return total + checkedCost(cost, at_point, home.entry);
}

Tour bestVariants(const std::vector<TourCluster>& clusters, const std::vector<int>& order,
                  const PointCost& cost) {
  checkClusters(clusters);
  checkOrder(clusters, order);
  TourModel model(clusters, cost);
  return optimiseVariants(model, order);
}

Tour naiveTour(const std::vector<TourCluster>& clusters, const PointCost& cost) {
  checkClusters(clusters);
  TourModel model(clusters, cost);
  return optimiseVariants(model, indexOrder(model));
}

void TourOptions::validate(const std::string& where) const {
  requireThat(max_passes >= 0, where, "max_passes", ">= 0", max_passes);
}

Tour solveTour(const std::vector<TourCluster>& clusters, const PointCost& cost,
               const TourOptions& options) {
  options.validate();
  checkClusters(clusters);
  TourModel model(clusters, cost);
  const int to_visit = model.clusterCount() - 1;
  if (to_visit <= 1) return optimiseVariants(model, indexOrder(model));
  if (to_visit <= std::min(options.exact_max_clusters, kMaxExactClusters)) return heldKarp(model);
  return heuristic(model, options);
}

Tour heuristicTour(const std::vector<TourCluster>& clusters, const PointCost& cost,
                   const TourOptions& options) {
  options.validate();
  checkClusters(clusters);
  TourModel model(clusters, cost);
  return heuristic(model, options);
}

double tourLowerBound(const std::vector<TourCluster>& clusters, const PointCost& cost) {
  checkClusters(clusters);
  TourModel model(clusters, cost);
  const int n = model.clusterCount();
  if (n == 1) return 0.0;
  // d(i, j): cheapest leg either way between any endpoints of the two clusters.
  const auto distance = [&](int i, int j) {
    double best = kInf;
    for (const int p : model.endpoints(i))
      for (const int q : model.endpoints(j))
        best = std::min({best, model.pointCost(p, q), model.pointCost(q, p)});
    return best;
  };
  double inner = 0.0;
  for (int c = 1; c < n; ++c) {
    double cheapest = kInf;
    for (int s = model.firstSlot(c); s < model.endSlot(c); ++s)
      cheapest = std::min(cheapest, model.inner(s));
    inner += cheapest;
  }
  std::vector<double> from_home;
  for (int c = 1; c < n; ++c) from_home.push_back(distance(0, c));
  if (n == 2) return inner + 2.0 * from_home[0];
  std::partial_sort(from_home.begin(), from_home.begin() + 2, from_home.end());
  // Prim's minimum spanning tree over clusters 1..n−1, O(n²) distances.
  double tree = 0.0;
  std::vector<double> reach(index(n), kInf);
  std::vector<bool> in_tree(index(n), false);
  in_tree[1] = true;
  for (int c = 2; c < n; ++c) reach[index(c)] = distance(1, c);
  for (int step = 2; step < n; ++step) {
    int nearest = -1;
    for (int c = 2; c < n; ++c)
      if (!in_tree[index(c)] && (nearest < 0 || reach[index(c)] < reach[index(nearest)]))
        nearest = c;
    tree += reach[index(nearest)];
    in_tree[index(nearest)] = true;
    for (int c = 2; c < n; ++c)
      if (!in_tree[index(c)]) reach[index(c)] = std::min(reach[index(c)], distance(nearest, c));
  }
  return inner + from_home[0] + from_home[1] + tree;
}

}  // namespace uavip::planning

namespace uavip::planning {

namespace {

/// Cost between path positions: node 0 is the start, node k the point order[k − 1].
struct PathCost {
  const std::vector<double>& m;  ///< (n + 1)² row-major, node 0 = start
  std::size_t stride;
  double operator()(int a, int b) const {
    return m[static_cast<std::size_t>(a) * stride + static_cast<std::size_t>(b)];
  }
};

/// Nearest neighbour from the start (ties to the lower index); nodes 1..n.
std::vector<int> nearestNeighbourOrder(const PathCost& c, int n) {
  std::vector<int> order;
  std::vector<char> used(static_cast<std::size_t>(n) + 1, 0);
  int at = 0;
  for (int k = 0; k < n; ++k) {
    int best = -1;
    for (int i = 1; i <= n; ++i) {
      if (!used[static_cast<std::size_t>(i)] && (best < 0 || c(at, i) < c(at, best))) best = i;
    }
    used[static_cast<std::size_t>(best)] = 1;
    order.push_back(best);
    at = best;
  }
  return order;
}

/// One pass of 2-opt over the open path 0, o[0], o[1], …: reversing positions i..j
/// replaces edges (i−1, i) and (j, j+1) by (i−1, j) and (i, j+1) (no edge after the
/// last node). True when some move shortened the path.
bool twoOptPass(const PathCost& c, std::vector<int>& o) {
  const std::size_t n = o.size();
  const auto at = [&](std::size_t k) { return k == 0 ? 0 : o[k - 1]; };  // position k, 0 = start
  bool improved = false;
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = i + 1; j <= n; ++j) {
      const double before = c(at(i - 1), at(i)) + (j < n ? c(at(j), at(j + 1)) : 0.0);
      const double after = c(at(i - 1), at(j)) + (j < n ? c(at(i), at(j + 1)) : 0.0);
      if (after < before - 1e-9) {
        std::reverse(o.begin() + static_cast<std::ptrdiff_t>(i - 1),
                     o.begin() + static_cast<std::ptrdiff_t>(j));
        improved = true;
      }
    }
  }
  return improved;
}

/// One pass of Or-opt: each node moved to the position where it costs least.
bool orOptPass(const PathCost& c, std::vector<int>& o) {
  bool improved = false;
  for (std::size_t k = 0; k < o.size(); ++k) {
    const int self = o[k];
    const int prev = k == 0 ? 0 : o[k - 1];
    const double saved =
        c(prev, self) + (k + 1 < o.size() ? c(self, o[k + 1]) - c(prev, o[k + 1]) : 0.0);
    std::vector<int> rest(o);
    rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(k));
    double best = saved - 1e-9;
    std::size_t best_pos = k;
    for (std::size_t q = 0; q <= rest.size(); ++q) {
      if (q == k) continue;
      const int a = q == 0 ? 0 : rest[q - 1];
      const double added = c(a, self) + (q < rest.size() ? c(self, rest[q]) - c(a, rest[q]) : 0.0);
      if (added < best) {
        best = added;
        best_pos = q;
      }
    }
    if (best_pos != k) {
      rest.insert(rest.begin() + static_cast<std::ptrdiff_t>(best_pos), self);
      o = std::move(rest);
      improved = true;
    }
  }
  return improved;
}

}  // namespace

std::vector<int> orderOpenPath(const Vec3& start, const PointList& points, const PointCost& cost,
                               int max_passes, int threads) {
  const std::size_t n = points.size();
  std::vector<double> m((n + 1) * (n + 1), 0.0);
  const auto node = [&](std::size_t i) -> const Vec3& { return i == 0 ? start : points[i - 1]; };
  // Row a writes only m[a][b > a] and m[b][a]: no two rows write one slot.
  parallelFor(n + 1, std::max(1, threads), [&](std::size_t a, std::size_t) {
    for (std::size_t b = a + 1; b <= n; ++b) {
      const double d = cost ? cost(static_cast<int>(a) - 1, static_cast<int>(b) - 1)
                            : (node(a) - node(b)).norm();
      m[a * (n + 1) + b] = m[b * (n + 1) + a] = d;
    }
  });
  const PathCost c{m, n + 1};
  std::vector<int> order = nearestNeighbourOrder(c, static_cast<int>(n));
  for (int pass = 0; pass < max_passes; ++pass) {
    const bool a = twoOptPass(c, order);
    const bool b = orOptPass(c, order);
    if (!a && !b) break;
  }
  for (auto& o : order) --o;  // nodes → point indices
  return order;
}

}  // namespace uavip::planning
