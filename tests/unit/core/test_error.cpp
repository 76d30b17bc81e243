#include <catch2/catch.hpp>

#include "core/error.h"

TEST_CASE("Error: message names the location and context chains", "[core]") {
  df::InvalidInput inner("face 3 refers to vertex 9 of 8", "horse/17.obj");
  CHECK(inner.message() == "face 3 refers to vertex 9 of 8 (horse/17.obj)");
  df::Error outer(inner, "reading frame 17");
  CHECK(outer.message() == "reading frame 17: face 3 refers to vertex 9 of 8 (horse/17.obj)");
  CHECK(df::Error("plain").message() == "plain");
}
