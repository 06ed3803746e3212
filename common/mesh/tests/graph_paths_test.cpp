#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "mesh/graph_paths.h"
#include "mesh/topology.h"
#include "testing/test_meshes.h"

TEST_CASE("edge distances on a grid: along edges, bounded, from several sources", "[mesh]") {
  // A 4 by 4 grid of unit cells: diagonals are edges of length sqrt(2).
  const gp::Mesh grid = gp::testing::make_grid(4, 4, 4.0, 4.0);
  const auto neighbors = gp::vertex_neighbors(grid.F, static_cast<int>(grid.V.rows()));
  const double inf = std::numeric_limits<double>::infinity();
  auto id = [](int i, int j) { return j * 5 + i; };
  std::vector<double> dist(static_cast<size_t>(grid.V.rows()), inf);
  std::vector<int> reached;
  gp::edge_distances(grid.V, neighbors, {id(0, 0)}, 10.0, dist, reached);
  CHECK(reached.size() == 25);
  CHECK(reached.front() == id(0, 0));
  CHECK(dist[id(4, 0)] == Approx(4.0));
  // The grid's diagonals run from (i, j) to (i + 1, j + 1): four of them.
  CHECK(dist[id(4, 4)] == Approx(4.0 * std::sqrt(2.0)));
  for (size_t k = 1; k < reached.size(); ++k) CHECK(dist[reached[k - 1]] <= dist[reached[k]]);
  // Bounded: only what lies within the limit, the rest stays infinite.
  std::fill(dist.begin(), dist.end(), inf);
  gp::edge_distances(grid.V, neighbors, {id(0, 0)}, 1.5, dist, reached);
  CHECK(reached.size() == 4);  // itself, two neighbours at 1, the diagonal at 1.41
  CHECK(std::isinf(dist[id(2, 0)]));
  // Two sources: each vertex takes the nearer.
  std::fill(dist.begin(), dist.end(), inf);
  gp::edge_distances(grid.V, neighbors, {id(0, 0), id(4, 0)}, 10.0, dist, reached);
  CHECK(dist[id(2, 0)] == Approx(2.0));
  CHECK(dist[id(3, 0)] == Approx(1.0));
}

TEST_CASE("dijkstra: parents, the stop rule, and ties by the lower parent id", "[mesh]") {
  // A square 0-1-3, 0-2-3 of unit edges: two shortest paths from 0 to 3 of
  // equal length, through 1 and through 2.
  const std::vector<std::vector<int>> neighbors{{1, 2}, {0, 3}, {0, 3}, {1, 2}};
  const auto unit = [](int, int) { return 1LL; };
  const long long unreached = std::numeric_limits<long long>::max();
  gp::GraphSearch<long long> s = gp::graph_search(neighbors.size(), unreached, true);
  gp::dijkstra(neighbors, {0}, unit, unreached, [](int) { return false; }, s, true);
  CHECK(s.dist == std::vector<long long>{0, 1, 1, 2});
  CHECK(gp::trace_parents(s.parent, 3) == std::vector<int>{0, 1, 3});
  CHECK(s.settled == std::vector<int>{0, 1, 2, 3});
  // Stopped once vertex 1 is settled: 3 is not reached.
  s = gp::graph_search(neighbors.size(), unreached, true);
  gp::dijkstra(neighbors, {0}, unit, unreached, [](int v) { return v == 1; }, s);
  CHECK(s.settled == std::vector<int>{0, 1});
  CHECK(s.dist[3] == unreached);
  // An edge of no length (the integer's largest value) is no edge.
  s = gp::graph_search(neighbors.size(), unreached, true);
  gp::dijkstra(
      neighbors, {0}, [&](int v, int w) { return (v == 3 || w == 3) ? unreached : 1LL; }, unreached,
      [](int) { return false; }, s);
  CHECK(s.dist[3] == unreached);
  CHECK(s.parent[3] == -1);
}
