#include <catch2/catch.hpp>
#include <filesystem>
#include <sstream>

#include "core/error.h"
#include "eval/metrics_table.h"
#include "helpers.h"

using df::eval::json_numbers;

TEST_CASE("metrics table: the numbers of a JSON object by dotted path, in file order", "[eval]") {
  const auto n = json_numbers(
      R"({"pred": "r.h5", "z": 3, "a": {"mean": 0.5, "per_step": [1, 2], "b": {"c": -1e-3}},
          "flag": true, "big": 12345678901})",
      "m.json");
  using P = std::pair<std::string, std::string>;
  CHECK(n ==
        std::vector<P>{{"z", "3"}, {"a.mean", "0.5"}, {"a.b.c", "-0.001"}, {"big", "12345678901"}});
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

TEST_CASE("metrics table: chosen columns by path, array elements and strings, values alone",
          "[eval]") {
  df::test::TempDir tmp;
  const std::string a = tmp / "a/m.json", b = tmp / "b/m.json";
  std::filesystem::create_directories(tmp / "a");
  std::filesystem::create_directories(tmp / "b");
  df::test::write_text(
      a, R"({"erms": 1.25, "levels": [{"kept": 3}, {"kept": 0}], "pred": "r.h5", "ok": true})");
  df::test::write_text(b, R"({"erms": 2, "levels": [{"kept": 5}]})");
  using df::eval::json_value;
  CHECK(json_value(R"({"levels": [{"kept": 3}, {"kept": 7}]})", "levels.1.kept", "m") == "7");
  CHECK(json_value(R"({"levels": [{"kept": 3}]})", "levels.1.kept", "m").empty());  // past the end
  CHECK(json_value(R"({"levels": [{"kept": 3}]})", "levels.x", "m").empty());       // not an index
  CHECK(json_value(R"({"a": {"b": 0.5}})", "a", "m").empty());                      // an object
  const auto t = df::eval::collect_metrics({a, b}, {}, {"levels.1.kept", "erms", "pred", "ok"});
  CHECK(t.names == std::vector<std::string>{"a", "b"});
  CHECK(t.cells ==
        std::vector<std::vector<std::string>>{{"0", "1.25", "r.h5", "true"}, {"", "2", "", ""}});
  std::ostringstream out;
  write_tsv(out, df::eval::collect_metrics({a}, {}, {"erms", "levels.0.kept"}, true), true);
  CHECK(out.str() == "1.25\t3\n");
  // a pipeline's value that a file lacks is an error naming the file and the path
  CHECK_THROWS_WITH(df::eval::collect_metrics({a, b}, {}, {"levels.1.kept"}, true),
                    Catch::Contains("has no number, string or boolean at 'levels.1.kept'"));
}
