#pragma once
/// \file
/// Order of a multi-surface flight: a generalised travelling-salesman tour that
/// leaves home, visits every cluster (a surface's photo stops) once in one of its
/// variants (e.g. its stops flown forward or reversed) and returns home.
///
/// Cluster 0 is HOME. Every function here takes the clusters as a vector whose
/// element 0 is home: it has exactly one variant, the UAV takes off from its exit
/// point and lands on its entry point (normally the same point), and its inner
/// cost is never counted. Clusters 1..n−1 are the ones to visit.
///
/// Costs of flying between points come from a callback, which may be expensive
/// (e.g. a path planner). Each public call evaluates every (from, to) pair of point
/// ids at most once: results are kept in a cache that lives for that call, of
/// O(P²) doubles for P distinct point ids.

#include <functional>
#include <string>
#include <vector>

#include "uavip/core/types.h"

namespace uavip::planning {

/// A place to visit, with the ways it can be flown.
struct TourCluster {
  /// One way of flying the cluster: enter at `entry`, fly `inner`, leave at `exit`.
  struct Variant {
    int entry{0};       ///< point id where the cluster is entered
    int exit{0};        ///< point id where the cluster is left
    double inner{0.0};  ///< cost flown inside the cluster [m]; non-negative
  };
  std::vector<Variant> variants;  ///< at least one
};

/// Cost of flying from one point id to another [m]. Must be non-negative; +inf marks
/// a leg that cannot be flown (a tour avoids it when it can). May be asymmetric.
using PointCost = std::function<double(int from_point, int to_point)>;

/// Options of the tour solver.
struct TourOptions {
  /// Held–Karp (exact dynamic programme over visited subset × last cluster × last
  /// variant) up to this many non-home clusters, the heuristic above. Memory and
  /// time grow as 2^n: values above 16 are used as 16; a negative value disables it.
  int exact_max_clusters{12};
  /// Improvement passes of the heuristic (each: every 2-opt and Or-opt move once);
  /// 0 = construction only.
  int max_passes{50};

  /// Throws InputError "<where>: max_passes must be >= 0, got …".
  void validate(const std::string& where = "tour") const;
};

/// A tour: home → order[0] → … → order.back() → home.
struct Tour {
  std::vector<int> order;    ///< cluster indices visited after home (home excluded), each once
  std::vector<int> variant;  ///< chosen variant of each visited cluster (same length as order)
  double cost{0.0};          ///< inner costs of the chosen variants + every leg, home legs too [m]
  /// True when the tour is known to be optimal: solved by Held–Karp, or at most one
  /// non-home cluster (a single order).
  bool exact{false};
};

/// Cost of `tour` (its `cost` field is ignored) [m]. Throws std::invalid_argument if
/// the clusters are invalid (see solveTour) or the tour does not visit every
/// non-home cluster exactly once with a valid variant.
double tourCost(const std::vector<TourCluster>& clusters, const Tour& tour, const PointCost& cost);

/// Best variants for a fixed cluster order: a dynamic programme over positions ×
/// variants, O(n·V²). Throws std::invalid_argument if `order` is not a permutation
/// of 1..n−1 or the clusters are invalid.
Tour bestVariants(const std::vector<TourCluster>& clusters, const std::vector<int>& order,
                  const PointCost& cost);

/// Clusters 1..n−1 by index, each in its best variant for that order: the baseline
/// a planner would fly without ordering.
Tour naiveTour(const std::vector<TourCluster>& clusters, const PointCost& cost);

/// The tour of least cost. Exact (Held–Karp, O(2^n·n²·V²)) when there are at most
/// options.exact_max_clusters non-home clusters; otherwise heuristicTour.
/// Deterministic. Throws std::invalid_argument if `clusters` is empty, a cluster has
/// no variant, home (cluster 0) has more than one variant, or the callback returns a
/// negative or NaN cost.
Tour solveTour(const std::vector<TourCluster>& clusters, const PointCost& cost,
               const TourOptions& options = {});

/// The heuristic alone (for tests and comparison with the exact solution): nearest
/// neighbour and the naive order as starts, the cheaper one improved by local search
/// until no move improves or options.max_passes. Moves: 2-opt (reverse a segment of
/// the order — its clusters are then flown the other way round) and Or-opt (move 1–3
/// consecutive clusters, kept or reversed, to every other position); every move is
/// judged with its variants re-optimised by the dynamic programme of bestVariants.
/// Never costlier than naiveTour. Deterministic; exact_max_clusters is ignored.
Tour heuristicTour(const std::vector<TourCluster>& clusters, const PointCost& cost,
                   const TourOptions& options = {});

/// A lower bound on the cost of every tour [m]: the sum over non-home clusters of
/// their cheapest inner cost, plus a 1-tree bound on the cluster graph whose edge
/// weight d(i, j) is the least of cost(p, q) and cost(q, p) over all endpoints p of
/// i and q of j (entry and exit points of any variant): the minimum spanning tree of
/// the non-home clusters plus the two cheapest edges from home (2·d(home, c) with a
/// single non-home cluster c); 0 when there is none.
///
/// Why it is a bound: every leg of a tour flies from an exit point of one cluster to
/// an entry point of the next, so it costs at least their d. Removing home from the
/// tour leaves a path through all non-home clusters, which is a spanning tree and so
/// weighs at least the MST; the two home legs reach two different clusters (the same
/// one twice when it is alone) and weigh at least the two cheapest home edges; each
/// chosen variant's inner cost is at least the cluster's cheapest. No symmetry or
/// triangle inequality of the costs is needed. The assumption is that a flown leg
/// from cluster i to j costs at least d(i, j) — true of tourCost by construction, and
/// of a real flight when the callback never overestimates the flown legs.
double tourLowerBound(const std::vector<TourCluster>& clusters, const PointCost& cost);

}  // namespace uavip::planning

namespace uavip::planning {

/// Order of a set of points flown as one open path from `start` (not returning):
/// nearest neighbour from start, then 2-opt (reverse a stretch) and Or-opt (move one
/// point elsewhere) until no move shortens the path or `max_passes`. Costs:
/// `cost(i, j)` for point indices, −1 = the start, taken as symmetric and asked once
/// per pair (empty = straight-line lengths), on up to `threads` threads (then `cost`
/// must be safe to call concurrently). Returns a permutation of 0..points.size()−1.
/// Deterministic. O(n²) memory and per pass; meant for a few thousand photo stops.
std::vector<int> orderOpenPath(const Vec3& start, const PointList& points,
                               const PointCost& cost = {}, int max_passes = 50, int threads = 1);

}  // namespace uavip::planning
