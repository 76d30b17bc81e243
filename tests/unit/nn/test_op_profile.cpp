#include <catch2/catch.hpp>

#include "nn/op_profile.h"
#include "nn/ops.h"

using df::nn::Matrix;
using df::nn::OpProfile;
using df::nn::Tape;

TEST_CASE("OpProfile names ops by the function that recorded them", "[nn]") {
  CHECK(OpProfile::op_name(
            "df::nn::Var<T> df::nn::matmul(df::nn::Var<T>, df::nn::Var<T>) [with T = float]") ==
        "matmul");
  CHECK(OpProfile::op_name(
            "df::nn::matmul_repeated<float>(df::nn::Var<float>, df::nn::Var<float>)::<lambda()>") ==
        "matmul_repeated");
  CHECK(OpProfile::op_name("leaf") == "leaf");
}

TEST_CASE("A profiled tape counts each op's calls, FLOPs and time; an unprofiled one nothing",
          "[nn]") {
  OpProfile profile;
  Tape<float>::profile_every_tape(&profile);
  Tape<float> t;
  Tape<float>::profile_every_tape(nullptr);
  Tape<float> quiet;  // made after: not profiled
  auto a = t.variable(Matrix<float>::Ones(4, 5)), b = t.variable(Matrix<float>::Ones(5, 3));
  auto y = df::nn::sum(df::nn::tanh(df::nn::matmul(a, b)));
  t.backward(y);
  auto q = quiet.variable(Matrix<float>::Ones(2, 2));
  quiet.backward(df::nn::sum(df::nn::tanh(q)));

  std::map<std::string, OpProfile::Row> rows;
  for (const auto& [name, r] : profile.rows()) rows[name] = r;
  REQUIRE(rows.count("matmul"));
  CHECK(rows["matmul"].calls == 1);
  CHECK(rows["matmul"].forward_flops == 2.0 * 4 * 5 * 3);
  CHECK(rows["matmul"].backward_flops == 2 * 2.0 * 4 * 5 * 3);  // both inputs want gradients
  CHECK(rows["tanh"].calls == 1);  // named after the op, not the element-wise helper
  CHECK(rows["tanh"].forward_flops == 0);
  CHECK(rows["tanh"].bytes == 2 * 4 * 3 * sizeof(float));  // its value, then its gradient
  CHECK(rows["leaf"].calls == 2);
  CHECK(rows["sum"].calls == 1);
  CHECK(rows["matmul"].backward_s > 0);
  CHECK(rows.size() == 4);  // nothing from the unprofiled tape
}
