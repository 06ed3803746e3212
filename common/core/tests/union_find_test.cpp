#include <catch2/catch.hpp>

#include "core/union_find.h"

TEST_CASE("union-find: a set's root is its smallest element, whatever the order of the joins", "[core]") {
  gp::UnionFind a(6), b(6);
  CHECK(a.unite(4, 5));
  CHECK(a.unite(5, 2));
  CHECK_FALSE(a.unite(2, 4));
  CHECK(a.unite(0, 1));
  // The same sets joined the other way round.
  CHECK(b.unite(1, 0));
  CHECK(b.unite(2, 5));
  CHECK(b.unite(4, 2));
  for (int v = 0; v < 6; ++v) CHECK(a.find(v) == b.find(v));
  CHECK(a.find(5) == 2);
  CHECK(a.find(1) == 0);
  CHECK(a.find(3) == 3);
  CHECK(a.size() == 6);
}
