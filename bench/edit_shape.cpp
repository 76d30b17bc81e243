// Benchmark of one edit-shape edit (geometry/subspace_edit): the factorisation for a handle set
// and the Levenberg-Marquardt solve, on the bumps surface at a chosen resolution (99: 10,000
// vertices) with K smooth local deformation directions (random centres, radii, rotation axes and
// stretches, Gaussian falloff) and N handles spread by furthest-point sampling, their targets in
// a shape the directions reach (random weights, reconstructed).
//   bench_edit [--resolution 99] [--components 60] [--handles 20] [--iters 3]
#include "apps/edit_shape.h"

#include <cmath>
#include <cstdio>
#include <random>

#include "core/tool.h"
#include "geometry/acap_features.h"
#include "geometry/subspace_edit.h"
#include "synth/meshseq.h"
#include "timing.h"

int main(int argc, char** argv) {
  df::Tool tool("bench_edit", "Time one edit-shape edit (see bench/run.sh).");
  int resolution = 99, K = 60, H = 20, iters = 3;
  tool.app()
      .add_option("--resolution", resolution, "Bumps grid resolution (vertices: (r+1)^2)")
      ->default_val(resolution);
  tool.app().add_option("--components", K, "Deformation directions")->default_val(K);
  tool.app().add_option("--handles", H, "Handles")->default_val(H);
  tool.app().add_option("--iters", iters, "Timed edits")->default_val(iters);
  return tool.run(argc, argv, [&] {
    using namespace df;
    synth::MeshSeqParams p;
    p.kind = synth::MeshSeqKind::bumps;
    p.resolution = resolution;
    p.frames = 1;
    const Mesh m = synth::MeshSequenceGenerator(p).rest();
    const int V = static_cast<int>(m.vertices.rows());
    const double diagonal =
        (m.vertices.colwise().maxCoeff() - m.vertices.colwise().minCoeff()).norm();
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::MatrixXd D = Eigen::MatrixXd::Zero(K, 9 * V);
    for (int k = 0; k < K; ++k) {
      const int centre = static_cast<int>(rng() % static_cast<unsigned>(V));
      const double radius = diagonal * (0.05 + 0.15 * (u(rng) + 1) / 2);
      const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized() * 0.8;
      const Eigen::Vector3d stretch(0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng));
      std::vector<Eigen::Vector3d> r(static_cast<std::size_t>(V));
      std::vector<Eigen::Matrix3d> S(static_cast<std::size_t>(V));
      for (int i = 0; i < V; ++i) {
        const double g = std::exp(-(m.vertices.row(i) - m.vertices.row(centre)).squaredNorm() /
                                  (radius * radius));
        r[static_cast<std::size_t>(i)] = g * axis;
        S[static_cast<std::size_t>(i)] = g * stretch.asDiagonal().toDenseMatrix();
      }
      std::vector<double> f(9 * static_cast<std::size_t>(V));
      geometry::pack_features(r, S, f.data());
      D.row(k) = Eigen::Map<const Eigen::RowVectorXd>(f.data(), 9 * V);
    }
    const auto id = geometry::identity_features();
    std::vector<double> base;
    for (int i = 0; i < V; ++i) base.insert(base.end(), id.begin(), id.end());
    Eigen::VectorXd truth(K);
    for (int k = 0; k < K; ++k) truth[k] = 0.5 * u(rng);
    Eigen::VectorXd f =
        Eigen::Map<const Eigen::VectorXd>(base.data(), 9 * V) + D.transpose() * truth;
    const Vertices shape = geometry::Reconstructor(m.vertices, m.faces).solve(f.data());
    const auto handles = apps::furthest_point_sample(m.vertices, H);
    Vertices pinned = m.vertices;
    for (int v : handles) pinned.row(v) = shape.row(v);
    geometry::SubspaceEditResult res;
    double factor = 0;
    const auto t = bench::time_iterations(0, iters, [&] {
      const geometry::SubspaceEditor ed(m.vertices, m.faces, handles, D, base);
      res = ed.edit(Eigen::VectorXd::Zero(K), pinned, {});
      factor = ed.factor_seconds();
    });
    double err = 0;
    for (int i = 0; i < V; ++i) err = std::max(err, (res.positions.row(i) - shape.row(i)).norm());
    std::printf(
        "| edit-shape, %d vertices, %d components, %d handles | %d steps | %.1f | %.1f | factor "
        "%.0f ms, largest error %.2g x diagonal |\n",
        V, K, H, res.iterations, t.median_ms, t.min_ms, 1e3 * factor, err / diagonal);
  });
}
