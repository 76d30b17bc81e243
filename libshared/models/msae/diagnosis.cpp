#include "models/msae/diagnosis.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <set>

#include "models/msae/components.h"

namespace df::models {

using Eigen::Index;

namespace {

// Singular values of the rows of `d` (relative to the largest, largest first) and how many
// exceed `floor` of the largest.
std::vector<double> relative_singular_values(const nn::Matrix<double>& d, double floor, int* rank) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(d * d.transpose(), Eigen::EigenvaluesOnly);
  std::vector<double> s;
  for (Index k = es.eigenvalues().size() - 1; k >= 0; --k) s.push_back(std::sqrt(std::max(0.0, es.eigenvalues()[k])));
  *rank = 0;
  const double top = s.empty() ? 0.0 : s[0];
  for (double& v : s) {
    v = top > 0 ? v / top : 0.0;
    if (v > floor) ++*rank;
  }
  return s;
}

// Each component's share of its block's deformation of each held-out shape, averaged.
std::vector<double> shares(const MsaeNet<float>& net, int b, const nn::Matrix<float>& z) {
  const int kz = net.blocks()[static_cast<std::size_t>(b)].kz;
  std::vector<double> share(static_cast<std::size_t>(kz), 0.0);
  if (z.rows() == 0) return share;
  const nn::Matrix<float> zero = net.decode(b, nn::Matrix<float>::Zero(1, kz));
  for (Index r = 0; r < z.rows(); ++r) {
    nn::Matrix<float> one_hot = nn::Matrix<float>::Zero(kz, kz);
    for (int k = 0; k < kz; ++k) one_hot(k, k) = z(r, k);
    const nn::Matrix<float> x = net.decode(b, one_hot);
    std::vector<double> norm(static_cast<std::size_t>(kz));
    double total = 0;
    for (int k = 0; k < kz; ++k) total += norm[static_cast<std::size_t>(k)] = static_cast<double>((x.row(k) - zero).norm());
    if (total > 0)
      for (int k = 0; k < kz; ++k) share[static_cast<std::size_t>(k)] += norm[static_cast<std::size_t>(k)] / total;
  }
  for (double& s : share) s /= static_cast<double>(z.rows());
  return share;
}

}  // namespace

MsaeDiagnosis diagnose_msae(const MsaeModel& m, const Components& comps, const nn::Matrix<float>& training,
                            const std::vector<nn::Matrix<float>>& codes, const nn::Matrix<float>& heldout) {
  const MsaeNet<float>& net = *m.net;
  const int V = net.n_vertices();
  MsaeDiagnosis d;
  d.n_training = static_cast<int>(training.rows());
  d.n_heldout = static_cast<int>(heldout.rows());
  {
    nn::Matrix<double> centred = training.cast<double>();
    const Eigen::RowVectorXd mean = centred.colwise().mean();
    centred.rowwise() -= mean;
    relative_singular_values(centred, 1e-6, &d.pca_rank);
  }
  const auto held_codes = block_codes(net, heldout);
  const auto centres = net.centres();
  const auto ref = geometry::identity_features(&m.normalization);
  d.levels.resize(static_cast<std::size_t>(net.config().levels()));
  std::vector<int> next(d.levels.size(), 0);  // next row of each level in comps
  for (std::size_t b = 0; b < net.blocks().size(); ++b) {
    const auto& block = net.blocks()[b];
    LevelDiagnosis& level = d.levels[static_cast<std::size_t>(block.level)];
    level.level = block.level;
    const auto& C = net.store().value(block.c);
    const double radius = m.config.d[static_cast<std::size_t>(block.level)];
    const auto share = shares(net, static_cast<int>(b), held_codes[b]);
    for (int k = 0; k < block.kz; ++k) {
      ComponentDiagnosis c;
      c.block = static_cast<int>(b);
      c.k = k;
      c.centre = centres[b][static_cast<std::size_t>(k)];
      c.weight_norm = static_cast<double>(C.row(k).norm());
      const auto src = std::find(m.geodesic_sources.begin(), m.geodesic_sources.end(), c.centre);
      if (src != m.geodesic_sources.end() && c.weight_norm > 0) {
        const auto& row = m.geodesic_rows[static_cast<std::size_t>(src - m.geodesic_sources.begin())];
        double in = 0;
        for (int i = 0; i < V; ++i)
          if (row[i] < radius) in += static_cast<double>(C.row(k).segment(9 * Index{i}, 9).squaredNorm());
        c.inside = in / (c.weight_norm * c.weight_norm);
      }
      const auto& lv = comps.levels[static_cast<std::size_t>(block.level)];
      const int row = next[static_cast<std::size_t>(block.level)]++;
      c.strength = lv.strength[static_cast<std::size_t>(row)];
      const auto dev = deformation_per_vertex(lv.features.row(row).data(), V, ref);
      const double peak = *std::max_element(dev.begin(), dev.end());
      for (double v : dev) c.support += peak > 0 && v >= 0.1 * peak ? 1 : 0;
      if (codes[b].rows()) c.code_min = codes[b].col(k).minCoeff(), c.code_max = codes[b].col(k).maxCoeff();
      c.share = share[static_cast<std::size_t>(k)];
      level.components.push_back(c);
    }
  }
  for (std::size_t l = 0; l < d.levels.size(); ++l) {
    LevelDiagnosis& level = d.levels[l];
    std::set<int> distinct;
    for (const auto& c : level.components) distinct.insert(c.centre);
    level.distinct_centres = static_cast<int>(distinct.size());
    nn::Matrix<double> dirs = comps.levels[l].features.cast<double>();
    for (Index j = 0; j < dirs.cols(); ++j) dirs.col(j).array() -= ref[static_cast<std::size_t>(j % 9)];
    level.singular_values = relative_singular_values(dirs, 1e-2, &level.effective_rank);
  }
  return d;
}

std::string format_diagnosis(const MsaeDiagnosis& d, const std::string& heldout_part) {
  std::string t = fmt::format(
      "MSAE diagnosis: {} training shapes (PCA spans {} direction(s)), {} {} shapes\n"
      "  |C_k|: the component's weights; inside: share of |C_k|^2 within Omega's radius of its centre;\n"
      "  support: vertices whose decoded deformation reaches 10% of its peak; strength: eq. 7;\n"
      "  codes: range over the training shapes; share: mean part of its block's deformation of the\n"
      "  {} shapes.\n",
      d.n_training, d.pca_rank, d.n_heldout, heldout_part, heldout_part);
  for (const auto& level : d.levels) {
    t += fmt::format("\nlevel {}: {} components, {} distinct centres; decoded directions' effective rank {} (singular values / largest: {:.3f})\n",
                     level.level, level.components.size(), level.distinct_centres, level.effective_rank,
                     fmt::join(level.singular_values, " "));
    t += fmt::format("  {:>5} {:>3} {:>6} {:>7} {:>6} {:>7} {:>8} {:>19} {:>6}\n", "block", "k", "centre", "|C_k|", "inside",
                     "support", "strength", "codes", "share");
    for (const auto& c : level.components)
      t += fmt::format("  {:>5} {:>3} {:>6} {:>7.3f} {:>6} {:>7} {:>8.4f} {:>9.3g}..{:<9.3g} {:>5.1f}%\n", c.block, c.k,
                       c.centre, c.weight_norm, c.inside < 0 ? std::string("-") : fmt::format("{:.2f}", c.inside),
                       c.support, c.strength, c.code_min, c.code_max, 100 * c.share);
  }
  return t;
}

}  // namespace df::models
