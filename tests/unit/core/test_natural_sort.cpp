#include <catch2/catch.hpp>

#include "core/natural_sort.h"

TEST_CASE("natural_sort: numbers compare by value", "[core]") {
  std::vector<std::string> v{"10.obj", "2.obj", "1.obj", "100.obj", "20.obj"};
  df::natural_sort(v);
  CHECK(v == std::vector<std::string>{"1.obj", "2.obj", "10.obj", "20.obj", "100.obj"});
}

TEST_CASE("natural_sort: mixed prefixes, zero padding and plain text", "[core]") {
  std::vector<std::string> v{
      "cat_000010.obj", "cat_reference.obj", "cat_000002.obj", "b1", "a10", "a9"};
  df::natural_sort(v);
  CHECK(v == std::vector<std::string>{"a9", "a10", "b1", "cat_000002.obj", "cat_000010.obj",
                                      "cat_reference.obj"});
  CHECK(df::natural_less("frame2", "frame02"));  // same value: fewer leading zeros first
  CHECK_FALSE(df::natural_less("frame02", "frame2"));
  CHECK(df::natural_less("frame2", "frame2b"));
  CHECK_FALSE(df::natural_less("x", "x"));
}
