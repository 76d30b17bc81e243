#include <catch2/catch.hpp>
#include <sstream>

#include "core/error.h"
#include "eval/metrics_table.h"

using df::eval::json_numbers;

TEST_CASE("metrics table: the numbers of a JSON object by dotted path, in file order", "[eval]") {
  const auto n = json_numbers(
      R"({"pred": "r.h5", "z": 3, "a": {"mean": 0.5, "per_step": [1, 2], "b": {"c": -1e-3}},
          "flag": true, "big": 12345678901})",
      "m.json");
  using P = std::pair<std::string, std::string>;
  CHECK(n == std::vector<P>{{"z", "3"}, {"a.mean", "0.5"}, {"a.b.c", "-0.001"}, {"big", "12345678901"}});
  CHECK_THROWS_AS(json_numbers("[1, 2]", "m.json"), df::InvalidInput);
  CHECK_THROWS_WITH(json_numbers("{\"a\": ", "m.json"), "not JSON");
}

TEST_CASE("metrics table: rows by file, columns the union, empty cells where missing", "[eval]") {
  df::eval::MetricsTable t;
  t.columns = {"erms", "sted.spatial"};
  t.names = {"kz5", "kz10"};
  t.cells = {{"1.5", ""}, {"2", "0.25"}};
  std::ostringstream out;
  write_tsv(out, t);
  CHECK(out.str() == "name\terms\tsted.spatial\nkz5\t1.5\t\nkz10\t2\t0.25\n");
  CHECK_THROWS_AS(df::eval::collect_metrics({"a.json"}, {"x", "y"}), df::UsageError);
  CHECK_THROWS_AS(df::eval::collect_metrics({"/nonexistent/m.json"}, {}), df::IOError);
}
