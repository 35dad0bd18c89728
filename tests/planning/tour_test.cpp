#include "uavip/planning/tour.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

namespace uavip::planning {
namespace {

using Point = std::array<double, 3>;

double distance(const Point& a, const Point& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

/// Clusters over points whose ids are indices into `points`; cluster 0 is home at point 0.
struct Instance {
  std::vector<Point> points;
  std::vector<TourCluster> clusters;
  PointCost euclidean() const {
    return [this](int a, int b) {
      return distance(points[static_cast<std::size_t>(a)], points[static_cast<std::size_t>(b)]);
    };
  }
};

/// Home plus `count` segments in a 100 m box (each up to ±10 m per axis around its
/// centre), every segment flown forward or backward; inner cost = segment length.
Instance randomSegments(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> in_box(0.0, 100.0);
  std::uniform_real_distribution<double> offset(-10.0, 10.0);
  Instance instance;
  instance.points.push_back({in_box(rng), in_box(rng), in_box(rng)});
  instance.clusters.push_back({{{0, 0, 0.0}}});
  for (int c = 0; c < count; ++c) {
    const Point centre{in_box(rng), in_box(rng), in_box(rng)};
    const Point a{centre[0] + offset(rng), centre[1] + offset(rng), centre[2] + offset(rng)};
    const Point b{centre[0] + offset(rng), centre[1] + offset(rng), centre[2] + offset(rng)};
    const int ia = static_cast<int>(instance.points.size());
    instance.points.push_back(a);
    instance.points.push_back(b);
    const double length = distance(a, b);
    instance.clusters.push_back({{{ia, ia + 1, length}, {ia + 1, ia, length}}});
  }
  return instance;
}

/// Every point-id pair's cost, for the brute force (ids are 0..points−1).
std::vector<std::vector<double>> costMatrix(std::size_t points, const PointCost& cost) {
  std::vector<std::vector<double>> matrix(points, std::vector<double>(points));
  for (std::size_t a = 0; a < points; ++a)
    for (std::size_t b = 0; b < points; ++b)
      matrix[a][b] = cost(static_cast<int>(a), static_cast<int>(b));
  return matrix;
}

/// Cost of visiting `order` in `variant`, from home and back, straight from the definition.
double definitionCost(const std::vector<TourCluster>& clusters, const std::vector<int>& order,
                      const std::vector<int>& variant,
                      const std::vector<std::vector<double>>& matrix) {
  const auto& home = clusters[0].variants[0];
  double total = 0.0;
  int at = home.exit;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const auto& v =
        clusters[static_cast<std::size_t>(order[i])].variants[static_cast<std::size_t>(variant[i])];
    total += matrix[static_cast<std::size_t>(at)][static_cast<std::size_t>(v.entry)] + v.inner;
    at = v.exit;
  }
  return total + matrix[static_cast<std::size_t>(at)][static_cast<std::size_t>(home.entry)];
}

/// Least cost over every variant combination of a fixed order (odometer over variants).
double bruteForceVariants(const std::vector<TourCluster>& clusters, const std::vector<int>& order,
                          const std::vector<std::vector<double>>& matrix) {
  double best = std::numeric_limits<double>::infinity();
  std::vector<int> variant(order.size(), 0);
  while (true) {
    best = std::min(best, definitionCost(clusters, order, variant, matrix));
    std::size_t digit = 0;
    while (digit < order.size()) {
      const int variants =
          static_cast<int>(clusters[static_cast<std::size_t>(order[digit])].variants.size());
      if (++variant[digit] < variants) break;
      variant[digit++] = 0;
    }
    if (digit == order.size()) return best;
  }
}

/// Least tour cost over all orders (std::next_permutation) × all variant combinations.
double bruteForceOptimum(const std::vector<TourCluster>& clusters,
                         const std::vector<std::vector<double>>& matrix) {
  std::vector<int> order(clusters.size() - 1);
  std::iota(order.begin(), order.end(), 1);
  double best = std::numeric_limits<double>::infinity();
  do {
    best = std::min(best, bruteForceVariants(clusters, order, matrix));
  } while (std::next_permutation(order.begin(), order.end()));
  return best;
}

bool isPermutationOfClusters(const Tour& tour, std::size_t clusters) {
  std::vector<int> sorted = tour.order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> expected(clusters - 1);
  std::iota(expected.begin(), expected.end(), 1);
  return sorted == expected && tour.variant.size() == tour.order.size();
}

/// A random instance with its brute-force optimum.
struct SolvedCase {
  Instance instance;
  double optimum{0.0};
};

/// 6 random instances for each of 1..8 non-home clusters (fixed seeds), solved by brute force.
const std::vector<SolvedCase>& bruteForceCases() {
  static const std::vector<SolvedCase> cases = [] {
    std::vector<SolvedCase> out;
    for (int count = 1; count <= 8; ++count) {
      for (unsigned seed = 0; seed < 6; ++seed) {
        SolvedCase c{randomSegments(count, 1000u * static_cast<unsigned>(count) + seed), 0.0};
        c.optimum = bruteForceOptimum(c.instance.clusters,
                                      costMatrix(c.instance.points.size(), c.instance.euclidean()));
        out.push_back(std::move(c));
      }
    }
    return out;
  }();
  return cases;
}

TEST(Tour, SolveEqualsBruteForceOptimum) {
  for (const auto& c : bruteForceCases()) {
    const PointCost cost = c.instance.euclidean();
    const Tour tour = solveTour(c.instance.clusters, cost);
    EXPECT_TRUE(tour.exact);
    ASSERT_TRUE(isPermutationOfClusters(tour, c.instance.clusters.size()));
    EXPECT_NEAR(tour.cost, c.optimum, 1e-9);
    EXPECT_NEAR(tourCost(c.instance.clusters, tour, cost), tour.cost, 1e-9);
  }
}

TEST(Tour, HeuristicIsNearOptimalAndNoWorseThanNaive) {
  double ratio_sum = 0.0;
  double worst = 1.0;
  int compared = 0;
  for (const auto& c : bruteForceCases()) {
    const PointCost cost = c.instance.euclidean();
    const Tour tour = heuristicTour(c.instance.clusters, cost);
    ASSERT_TRUE(isPermutationOfClusters(tour, c.instance.clusters.size()));
    EXPECT_NEAR(tourCost(c.instance.clusters, tour, cost), tour.cost, 1e-9);
    EXPECT_GE(tour.cost, c.optimum - 1e-9);
    EXPECT_LE(tour.cost, naiveTour(c.instance.clusters, cost).cost + 1e-9);
    if (c.instance.clusters.size() - 1 < 4) continue;  // the 30 instances of 4..8 clusters
    const double ratio = tour.cost / c.optimum;
    ratio_sum += ratio;
    worst = std::max(worst, ratio);
    ++compared;
  }
  ASSERT_EQ(compared, 30);
  std::cout << "heuristic / optimum over " << compared << " instances: mean "
            << ratio_sum / compared << ", worst " << worst << "\n";
  EXPECT_LE(ratio_sum / compared, 1.01);
  EXPECT_LE(worst, 1.05);
}

TEST(Tour, LowerBoundIsPositiveAndBelowOptimum) {
  for (const auto& c : bruteForceCases()) {
    const double bound = tourLowerBound(c.instance.clusters, c.instance.euclidean());
    EXPECT_GT(bound, 0.0);
    EXPECT_LE(bound, c.optimum + 1e-9);
  }
}

TEST(Tour, BestVariantsEqualsBruteForceForFixedOrder) {
  std::mt19937 rng(7);
  for (int count = 1; count <= 9; ++count) {
    const Instance instance = randomSegments(count, 500u + static_cast<unsigned>(count));
    const PointCost cost = instance.euclidean();
    std::vector<int> order(static_cast<std::size_t>(count));
    std::iota(order.begin(), order.end(), 1);
    std::shuffle(order.begin(), order.end(), rng);
    const Tour tour = bestVariants(instance.clusters, order, cost);
    EXPECT_EQ(tour.order, order);
    EXPECT_NEAR(
        tour.cost,
        bruteForceVariants(instance.clusters, order, costMatrix(instance.points.size(), cost)),
        1e-9);
    EXPECT_NEAR(tourCost(instance.clusters, tour, cost), tour.cost, 1e-9);
  }
}

/// `count` single-point clusters on a circle of radius 50 m, home at angle 0, the
/// others given in a scrambled index order.
Instance scrambledCircle(int count) {
  std::vector<int> position(static_cast<std::size_t>(count - 1));
  std::iota(position.begin(), position.end(), 1);
  std::shuffle(position.begin(), position.end(), std::mt19937(11));
  position.insert(position.begin(), 0);
  Instance instance;
  const double pi = std::acos(-1.0);
  for (int c = 0; c < count; ++c) {
    const double angle = 2.0 * pi * position[static_cast<std::size_t>(c)] / count;
    instance.points.push_back({50.0 * std::cos(angle), 50.0 * std::sin(angle), 10.0});
    instance.clusters.push_back({{{c, c, 0.0}}});
  }
  return instance;
}

/// The tour flies the circle around (one way or the other) and costs its polygon.
void expectAroundCircle(const Instance& instance, const Tour& tour) {
  const int count = static_cast<int>(instance.clusters.size());
  const double pi = std::acos(-1.0);
  EXPECT_NEAR(tour.cost, count * 2.0 * 50.0 * std::sin(pi / count), 1e-9);
  std::vector<int> angles{0};  // positions on the circle in visiting order, home first
  const double step = 2.0 * pi / count;
  for (const int c : tour.order) {
    const Point& p = instance.points[static_cast<std::size_t>(c)];
    angles.push_back(static_cast<int>(std::lround(std::atan2(p[1], p[0]) / step + count)) % count);
  }
  const int direction = angles[1] == 1 ? 1 : count - 1;
  for (std::size_t i = 1; i < angles.size(); ++i)
    EXPECT_EQ(angles[i], (angles[i - 1] + direction) % count);
}

TEST(Tour, ScrambledCircleIsFlownAround) {
  const Instance small = scrambledCircle(12);
  const Tour exact = solveTour(small.clusters, small.euclidean());
  EXPECT_TRUE(exact.exact);
  expectAroundCircle(small, exact);
  const Instance large = scrambledCircle(40);
  const Tour heuristic = solveTour(large.clusters, large.euclidean());
  EXPECT_FALSE(heuristic.exact);
  expectAroundCircle(large, heuristic);
}

TEST(Tour, AsymmetricCostsAndMixedVariantCountsStayExact) {
  for (unsigned seed = 0; seed < 8; ++seed) {
    Instance instance = randomSegments(6, 77u + seed);
    // Cluster c gets 1, 2 or 3 variants; the third flies out and back, entering and
    // leaving at the segment's first point.
    for (std::size_t c = 1; c < instance.clusters.size(); ++c) {
      auto& variants = instance.clusters[c].variants;
      if (c % 3 == 1) variants.pop_back();
      if (c % 3 == 0)
        variants.push_back({variants[0].entry, variants[0].entry, 2.0 * variants[0].inner});
    }
    // Every metre climbed costs 2 m more than the straight line; descending costs nothing extra.
    const PointCost climb = [&instance](int a, int b) {
      const Point& p = instance.points[static_cast<std::size_t>(a)];
      const Point& q = instance.points[static_cast<std::size_t>(b)];
      return distance(p, q) + 2.0 * std::max(0.0, q[2] - p[2]);
    };
    const double optimum =
        bruteForceOptimum(instance.clusters, costMatrix(instance.points.size(), climb));
    const Tour exact = solveTour(instance.clusters, climb);
    EXPECT_NEAR(exact.cost, optimum, 1e-9);
    EXPECT_NEAR(tourCost(instance.clusters, exact, climb), optimum, 1e-9);
    EXPECT_GE(heuristicTour(instance.clusters, climb).cost, optimum - 1e-9);
    EXPECT_LE(tourLowerBound(instance.clusters, climb), optimum + 1e-9);
  }
}

TEST(Tour, EachPointPairIsEvaluatedAtMostOncePerCall) {
  const Instance small = randomSegments(8, 3);
  const Instance large = randomSegments(25, 4);
  std::map<std::pair<int, int>, int> calls;
  const auto counting = [&calls](const Instance& instance) -> PointCost {
    return [&calls, &instance](int a, int b) {
      ++calls[{a, b}];
      return distance(instance.points[static_cast<std::size_t>(a)],
                      instance.points[static_cast<std::size_t>(b)]);
    };
  };
  const auto expectOncePerPair = [&calls](const char* what) {
    EXPECT_FALSE(calls.empty()) << what;
    for (const auto& [pair, count] : calls)
      EXPECT_EQ(count, 1) << what << ": (" << pair.first << ", " << pair.second << ")";
    calls.clear();
  };
  solveTour(small.clusters, counting(small));
  expectOncePerPair("exact");
  heuristicTour(large.clusters, counting(large));
  expectOncePerPair("heuristic");
  tourLowerBound(large.clusters, counting(large));
  expectOncePerPair("lower bound");
  naiveTour(large.clusters, counting(large));
  expectOncePerPair("naive");
}

TEST(Tour, InvalidInputThrows) {
  const Instance instance = randomSegments(3, 9);
  const PointCost cost = instance.euclidean();
  EXPECT_THROW(solveTour({}, cost), std::invalid_argument);
  auto no_variant = instance.clusters;
  no_variant[2].variants.clear();
  EXPECT_THROW(solveTour(no_variant, cost), std::invalid_argument);
  EXPECT_THROW(heuristicTour(no_variant, cost), std::invalid_argument);
  EXPECT_THROW(tourLowerBound(no_variant, cost), std::invalid_argument);
  auto two_homes = instance.clusters;
  two_homes[0].variants.push_back(two_homes[0].variants[0]);
  EXPECT_THROW(solveTour(two_homes, cost), std::invalid_argument);
  EXPECT_THROW(bestVariants(instance.clusters, {1, 2}, cost), std::invalid_argument);
  EXPECT_THROW(bestVariants(instance.clusters, {1, 2, 2}, cost), std::invalid_argument);
  EXPECT_THROW(bestVariants(instance.clusters, {0, 1, 2}, cost), std::invalid_argument);
  Tour bad_variant{{1, 2, 3}, {0, 2, 0}, 0.0, false};
  EXPECT_THROW(tourCost(instance.clusters, bad_variant, cost), std::invalid_argument);
  const PointCost negative = [](int, int) { return -1.0; };
  EXPECT_THROW(solveTour(instance.clusters, negative), std::invalid_argument);
  const PointCost not_a_number = [](int, int) { return std::nan(""); };
  EXPECT_THROW(heuristicTour(instance.clusters, not_a_number), std::invalid_argument);
}

TEST(Tour, OnlyHomeGivesAnEmptyTour) {
  const std::vector<TourCluster> home{{{{5, 5, 0.0}}}};
  int calls = 0;
  const PointCost cost = [&calls](int, int) {
    ++calls;
    return 1.0;
  };
  for (const Tour& tour :
       {solveTour(home, cost), heuristicTour(home, cost), naiveTour(home, cost)}) {
    EXPECT_TRUE(tour.order.empty());
    EXPECT_TRUE(tour.variant.empty());
    EXPECT_EQ(tour.cost, 0.0);
  }
  EXPECT_EQ(tourLowerBound(home, cost), 0.0);
  EXPECT_EQ(calls, 0);
}

TEST(Tour, ExactLimitChoosesTheSolver) {
  const Instance instance = randomSegments(7, 21);
  const PointCost cost = instance.euclidean();
  TourOptions options;
  options.exact_max_clusters = 6;
  const Tour heuristic = solveTour(instance.clusters, cost, options);
  EXPECT_FALSE(heuristic.exact);
  options.exact_max_clusters = 7;
  const Tour exact = solveTour(instance.clusters, cost, options);
  EXPECT_TRUE(exact.exact);
  EXPECT_GE(heuristic.cost, exact.cost - 1e-9);
}

TEST(Tour, LargeInstanceIsBoundedAndDeterministic) {
  const Instance instance = randomSegments(60, 2024);
  const PointCost cost = instance.euclidean();
  const Tour first = solveTour(instance.clusters, cost);
  const Tour second = solveTour(instance.clusters, cost);
  ASSERT_TRUE(isPermutationOfClusters(first, instance.clusters.size()));
  EXPECT_FALSE(first.exact);
  EXPECT_EQ(first.order, second.order);
  EXPECT_EQ(first.variant, second.variant);
  EXPECT_EQ(first.cost, second.cost);
  EXPECT_NEAR(tourCost(instance.clusters, first, cost), first.cost, 1e-9);
  const double naive = naiveTour(instance.clusters, cost).cost;
  const double bound = tourLowerBound(instance.clusters, cost);
  EXPECT_LE(first.cost, naive);
  EXPECT_GE(first.cost, bound);
  std::cout << "60 clusters: naive " << naive << " m, tour " << first.cost << " m, lower bound "
            << bound << " m\n";
}

/// Wall time of one call [ms].
template <typename Call>
double milliseconds(Call call) {
  const auto start = std::chrono::steady_clock::now();
  call();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

TEST(Tour, ReportsSolveTimes) {
  const Instance twelve = randomSegments(12, 12);
  const Instance sixty_four = randomSegments(64, 64);
  Tour exact, heuristic;
  const double exact_ms =
      milliseconds([&] { exact = solveTour(twelve.clusters, twelve.euclidean()); });
  const double heuristic_ms =
      milliseconds([&] { heuristic = solveTour(sixty_four.clusters, sixty_four.euclidean()); });
  EXPECT_TRUE(exact.exact);
  EXPECT_FALSE(heuristic.exact);
  std::cout << "Held-Karp, 12 clusters x 2 variants: " << exact_ms << " ms\n"
            << "heuristic, 64 clusters x 2 variants: " << heuristic_ms << " ms (cost "
            << heuristic.cost << " m, lower bound "
            << tourLowerBound(sixty_four.clusters, sixty_four.euclidean()) << " m)\n";
}

}  // namespace
}  // namespace uavip::planning
