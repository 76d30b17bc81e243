// Small learning problems that must converge, deterministically for a seed.
#include <catch2/catch.hpp>

#include "geometry/mesh_topology.h"
#include "nn/adam.h"
#include "nn/layers.h"
#include "nn/train_step.h"
#include "synth/meshseq.h"

using namespace df::nn;

TEST_CASE("nn learning: an LSTM learns to output its input delayed by 3 steps", "[nn]") {
  df::Rng init(3, 0), data(3, 1);
  ParameterStore<float> s;
  StackedLstm<float> lstm(s, "lstm", 1, 24, 1, init);
  Linear<float> head(s, "head", 24, 1, init);
  AdamOptions o;
  o.lr = 0.01;
  Adam<float> adam(s.size(), o);
  const int batch = 16, steps = 12, delay = 3;
  Tape<float> t;
  float first = 0, last = 0;
  for (int it = 0; it < 400; ++it) {
    std::vector<Matrix<float>> x(steps, Matrix<float>(batch, 1));
    for (auto& m : x)
      for (int b = 0; b < batch; ++b) m(b, 0) = static_cast<float>(data.uniform(-1, 1));
    last = train_step<float>(t, s, adam, [&](Tape<float>& t, const Bound<float>& p) {
      std::vector<Var<float>> xs;
      for (auto& m : x) xs.push_back(t.constant(m));
      auto states = lstm.constant_states(t, batch, 0.0f);
      auto h = lstm.run(p, xs, states);
      std::vector<Var<float>> losses;
      for (int k = delay; k < steps; ++k)
        losses.push_back(
            mse(head(p, h[static_cast<std::size_t>(k)]), xs[static_cast<std::size_t>(k - delay)]));
      return scale(sum(concat_cols(losses)), 1.0f / static_cast<float>(losses.size()));
    });
    if (it == 0) first = last;
  }
  INFO("loss " << first << " -> " << last);
  CHECK(first > 0.25f);  // variance of U(-1, 1) is 1/3
  CHECK(last < 0.02f);
}

TEST_CASE(
    "nn learning: a MeshConv autoencoder cuts reconstruction loss 10x on a synthetic sequence",
    "[nn]") {
  df::synth::MeshSeqParams sp;
  sp.kind = df::synth::MeshSeqKind::flag;
  sp.resolution = 8;
  sp.frames = 40;
  df::synth::MeshSequenceGenerator g(sp);
  const auto& rest = g.rest();
  const auto V = rest.vertices.rows();
  auto topo = df::geometry::mesh_topology(rest.faces, static_cast<int>(V));
  auto adj = neighbour_mean_operator<float>(static_cast<int>(V), topo.edges);
  Matrix<float> X(sp.frames, V * 3);  // displacements from the rest shape
  for (int f = 0; f < sp.frames; ++f) {
    df::Vertices d = g.frame(f) - rest.vertices;
    for (Eigen::Index k = 0; k < V * 3; ++k) X(f, k) = static_cast<float>(d.data()[k]);
  }
  df::Rng init(5, 0);
  ParameterStore<float> s;
  MeshConv<float> enc(s, "enc", 3, 3, adj, init);
  Linear<float> down(s, "down", 3 * V, 8, init), up(s, "up", 8, 3 * V, init);
  int dec_bias = s.add("dec.bias", 1, 3);
  AdamOptions o;
  o.lr = 0.003;
  Adam<float> adam(s.size(), o);
  Tape<float> t;
  float first = 0, last = 0;
  for (int it = 0; it < 400; ++it) {
    last = train_step<float>(t, s, adam, [&](Tape<float>& t, const Bound<float>& p) {
      Var<float> x = t.constant(X);
      Var<float> z = tanh(down(p, tanh(enc(p, x))));
      return mse(enc.tied_transpose(p, up(p, z), p[dec_bias]), x);
    });
    if (it == 0) first = last;
  }
  INFO("loss " << first << " -> " << last);
  CHECK(last < first / 10);
}
