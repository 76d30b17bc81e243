// The model kinds' shared parts (io/model_file): the training state and the log read back as
// written, and the checks that name what does not fit.
#include <catch2/catch.hpp>

#include "helpers.h"
#include "io/model_file.h"

using namespace df;
using df::test::error_message;
using df::test::TempDir;

TEST_CASE("model file: parameters, Adam states, RNG state and log round-trip", "[io]") {
  TempDir dir;
  const auto path = dir.path() / "m.h5";
  h5::RowMatrix<float> w(2, 3);
  w << 1, 2, 3, 4, 5, 6;
  const std::vector<float> m{0.5f, -1}, v{2, 3};
  {
    h5::File f(path, h5::File::Mode::create);
    io::write_iteration(f, 42);
    io::write_param(f, "enc/w", w);
    io::write_param_order(f, {"enc/w"});
    io::write_adam_state(f, io::model_layout::optimizer(), m, v, 7);
    io::write_adam_state(f, io::model_layout::optimizer("gen"), v, m, 9);
    io::write_rng_state(f, {{1, 2, 3, 4}, true, 0.25});
    io::write_training_log(f, {1, 10, 2, 20}, {"iteration", "loss"}, {3, 0.5});
  }
  h5::File f(path, h5::File::Mode::read);
  CHECK(io::read_iteration(f) == 42);
  CHECK(io::read_param_order(f) == std::vector<std::string>{"enc/w"});
  CHECK(io::read_param(f, "enc/w", 2, 3) == w);
  const auto a = io::read_adam_state(f, "/optimizer", 2),
             g = io::read_adam_state(f, "/optimizers/gen", 2);
  CHECK((a.m == m && a.v == v && a.step == 7));
  CHECK((g.m == v && g.v == m && g.step == 9));
  const auto r = io::read_rng_state(f);
  CHECK((r.state == std::array<std::uint64_t, 4>{1, 2, 3, 4} && r.has_spare && r.spare == 0.25));
  const auto log = io::read_training_log(f);
  CHECK(log.rows == std::vector<double>{1, 10, 2, 20});
  CHECK(log.columns == "iteration loss");
  CHECK(log.unprinted == std::vector<double>{3, 0.5});

  SECTION("a parameter or an optimizer of another shape is refused, naming the dataset") {
    CHECK_THAT(error_message([&] { (void)io::read_param(f, "enc/w", 3, 2); }),
               Catch::Contains("parameter 'enc/w' is [2,3], the model expects [3,2]") &&
                   Catch::Contains("/params/enc/w"));
    CHECK_THAT(error_message([&] { (void)io::read_adam_state(f, "/optimizer", 3); }),
               Catch::Contains("optimizer state does not match") && Catch::Contains("/optimizer"));
  }
}

TEST_CASE("model file: no log reads as empty", "[io]") {
  TempDir dir;
  const auto path = dir.path() / "m.h5";
  {
    h5::File f(path, h5::File::Mode::create);
    io::write_training_log(f, {}, {"iteration"}, {});
  }
  h5::File f(path, h5::File::Mode::read);
  const auto log = io::read_training_log(f);
  CHECK((log.rows.empty() && log.unprinted.empty() && log.columns.empty()));
}
