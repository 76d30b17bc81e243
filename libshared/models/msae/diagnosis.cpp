#include "models/msae/diagnosis.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <set>

#include "core/error.h"
#include "models/msae/components.h"

namespace df::models {

using Eigen::Index;

namespace {

// Singular values of the rows of `d` (relative to the largest, largest first) and how many
// exceed `floor` of the largest.
std::vector<double> relative_singular_values(const nn::Matrix<double>& d, double floor, int* rank) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(d * d.transpose(),
                                                          Eigen::EigenvaluesOnly);
  std::vector<double> s;
  for (Index k = es.eigenvalues().size() - 1; k >= 0; --k)
    s.push_back(std::sqrt(std::max(0.0, es.eigenvalues()[k])));
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
    for (int k = 0; k < kz; ++k)
      total += norm[static_cast<std::size_t>(k)] = static_cast<double>((x.row(k) - zero).norm());
    if (total > 0)
      for (int k = 0; k < kz; ++k)
        share[static_cast<std::size_t>(k)] += norm[static_cast<std::size_t>(k)] / total;
  }
  for (double& s : share) s /= static_cast<double>(z.rows());
  return share;
}

// The projection of m's rows onto its top `rank` left singular vectors (m [n, cols]).
nn::Matrix<double> top_projection(const nn::Matrix<double>& m, int rank) {
  const Index n = m.rows();
  if (rank >= n) return m;
  if (rank <= 0) return nn::Matrix<double>::Zero(n, m.cols());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(m * m.transpose());
  const Eigen::MatrixXd u = es.eigenvectors().rightCols(rank);  // eigenvalues ascend
  return u * (u.transpose() * m);
}

SecondLevelDiagnosis second_level(const MsaeNet<float>& net, const nn::Matrix<float>& training) {
  SecondLevelDiagnosis s;
  const nn::Matrix<double> x = training.cast<double>();
  const nn::Matrix<double> r = x - net.reconstruct(training, 1).cast<double>();
  const double total = r.squaredNorm();
  if (!(total > 0)) return s;  // level 0 reconstructs the training shapes: nothing to split
  std::vector<int> ranks;
  for (int c : net.blocks()[0].children)
    ranks.push_back(net.blocks()[static_cast<std::size_t>(c)].kz);
  s.children = static_cast<int>(ranks.size());
  for (int k : ranks) s.components += k;
  s.child_kz = *std::max_element(ranks.begin(), ranks.end());
  const bool attention = net.config().attention && ranks.size() > 1;
  const nn::Matrix<double> masks =
      attention ? net.attention_masks(0).cast<double>() : nn::Matrix<double>();
  double fed = total;
  if (attention) {
    fed = 0;
    for (Index k = 0; k < masks.rows(); ++k)
      for (Index i = 0; i < masks.cols(); ++i)
        fed += masks(k, i) * masks(k, i) * r.middleCols(9 * i, 9).squaredNorm();
  }
  s.fed = fed / total;
  s.left_trained = (x - net.reconstruct(training, 2).cast<double>()).squaredNorm() / total;
  s.left_linear = (r - best_linear_children(r, masks, ranks)).squaredNorm() / total;
  s.left_one = (r - top_projection(r, s.components)).squaredNorm() / total;
  s.left_one_child = (r - top_projection(r, s.child_kz)).squaredNorm() / total;
  return s;
}

}  // namespace

ChildrenErrors children_errors(const MsaeNet<float>& net, const nn::Matrix<float>& shapes) {
  ChildrenErrors out;
  if (net.config().levels() < 2 || shapes.rows() == 0) return out;
  std::vector<nn::Matrix<float>> codes;
  net.reconstruct(shapes, 2, &codes);
  const nn::Matrix<float> r = shapes - net.decode(0, codes[0]);  // the residual after level 0
  out.residual = r.cast<double>().squaredNorm();
  const nn::Matrix<float> masks =
      net.config().attention ? net.attention_masks(0) : nn::Matrix<float>();
  nn::Matrix<double> sum = nn::Matrix<double>::Zero(r.rows(), r.cols());
  for (int c : net.blocks()[0].children) {
    const auto& child = net.blocks()[static_cast<std::size_t>(c)];
    const nn::Matrix<double> e = (net.child_input(child, r, masks.size() ? &masks : nullptr) -
                                  net.decode(c, codes[static_cast<std::size_t>(c)]))
                                     .cast<double>();
    out.own += e.squaredNorm();
    sum += e;
  }
  out.whole = sum.squaredNorm();
  return out;
}

nn::Matrix<double> best_linear_children(const nn::Matrix<double>& r,
                                        const nn::Matrix<double>& masks,
                                        const std::vector<int>& ranks) {
  if (masks.size() == 0) return top_projection(r, ranks.empty() ? 0 : ranks[0]);
  if (masks.cols() * 9 != r.cols() || static_cast<std::size_t>(masks.rows()) != ranks.size())
    throw Error("best_linear_children: masks [K, V] against r [n, 9V] and K ranks");
  nn::Matrix<double> sum = nn::Matrix<double>::Zero(r.rows(), r.cols());
  for (Index k = 0; k < masks.rows(); ++k) {
    nn::Matrix<double> in = r;
    for (Index i = 0; i < masks.cols(); ++i) in.middleCols(9 * i, 9) *= masks(k, i);
    sum += top_projection(in, ranks[static_cast<std::size_t>(k)]);
  }
  return sum;
}

MsaeDiagnosis diagnose_msae(const MsaeModel& m, const Components& comps,
                            const nn::Matrix<float>& training,
                            const std::vector<nn::Matrix<float>>& codes,
                            const nn::Matrix<float>& heldout) {
  const MsaeNet<float>& net = *m.net;
  const int V = net.n_vertices();
  MsaeDiagnosis d;
  d.n_training = static_cast<int>(training.rows());
  d.n_vertices = V;
  d.eps1 = comps.eps1;
  d.eps2 = comps.eps2;
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
        const auto& row =
            m.geodesic_rows[static_cast<std::size_t>(src - m.geodesic_sources.begin())];
        double in = 0;
        for (int i = 0; i < V; ++i)
          if (row[i] < radius)
            in += static_cast<double>(C.row(k).segment(9 * Index{i}, 9).squaredNorm());
        c.inside = in / (c.weight_norm * c.weight_norm);
      }
      const auto& lv = comps.levels[static_cast<std::size_t>(block.level)];
      const int row = next[static_cast<std::size_t>(block.level)]++;
      c.eq7 =
          strength_parts(deformation_per_vertex(lv.features.row(row).data(), V, ref), comps.eps1);
      if (codes[b].rows())
        c.code_min = codes[b].col(k).minCoeff(), c.code_max = codes[b].col(k).maxCoeff();
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
    for (Index j = 0; j < dirs.cols(); ++j)
      dirs.col(j).array() -= ref[static_cast<std::size_t>(j % 9)];
    level.singular_values = relative_singular_values(dirs, 1e-2, &level.effective_rank);
  }
  if (!net.blocks()[0].children.empty() && training.rows() > 0) {
    d.second = second_level(net, training);
    const ChildrenErrors e = children_errors(net, heldout);
    if (d.second.children > 0 && e.residual > 0) {
      d.second.heldout_own = e.own / e.residual;
      d.second.heldout_whole = e.whole / e.residual;
      d.second.heldout_residual = e.residual / static_cast<double>(heldout.rows());
    }
  }
  return d;
}

bool CollapseSigns::collapsed() const {
  return 2 * distinct_centres < components || 2 * wide > components || constant > 0;
}

std::string CollapseSigns::describe(const MsaeConfig& config) const {
  if (!collapsed()) return "";
  std::vector<std::string> signs, remedies;
  if (2 * distinct_centres < components) {
    signs.push_back(fmt::format("{} distinct centres", distinct_centres));
    if (config.centres != Centres::spread)
      remedies.push_back("--centres spread");
    else if (config.centre_separation == 0)
      remedies.push_back("--centre-separation 1");
  }
  if (2 * wide > components) {
    signs.push_back(fmt::format("{} spanning over 80% of the mesh", wide));
    if (config.support != Support::hard)
      remedies.push_back(config.support == Support::soft ? "--support proximal" : "--support hard");
  }
  if (constant > 0) {
    signs.push_back(
        fmt::format("{} carrying a near-constant code: the mean deformation", constant));
    if (!config.centre_features) remedies.push_back("--centre-features");
  }
  const std::string remedy =
      remedies.empty() ? std::string("fewer level-0 components (--kz) or more training shapes")
                       : fmt::format("{}", fmt::join(remedies, " "));
  return fmt::format(
      "level 0's {} components have collapsed ({}): unseen shapes will be reconstructed "
      "poorly; try {}",
      components, fmt::join(signs, ", "), remedy);
}

CollapseSigns collapse_signs(const MsaeModel& m, const nn::Matrix<float>& data,
                             const std::vector<std::int64_t>& training) {
  const MsaeNet<float>& net = *m.net;
  CollapseSigns s;
  const int kz = net.blocks()[0].kz, V = net.n_vertices();
  s.components = kz;
  const auto centres = net.centres()[0];
  s.distinct_centres = static_cast<int>(std::set<int>(centres.begin(), centres.end()).size());
  if (training.empty()) return s;
  const nn::Matrix<float> z = block_codes(net, data, training, 1)[0];  // AE₀'s codes
  // the components as extract-components decodes them, their supports as --report counts them
  const auto ref = geometry::identity_features(&m.normalization);
  ComponentLevel decoded;
  decode_block(net, 0, z, centres, ref, io::Components{}.eps1, decoded);
  std::vector<double> size(static_cast<std::size_t>(kz)), range(size.size());
  for (int k = 0; k < kz; ++k) {
    const double lo = z.col(k).minCoeff(), hi = z.col(k).maxCoeff();
    size[static_cast<std::size_t>(k)] = std::max(std::abs(lo), std::abs(hi));
    range[static_cast<std::size_t>(k)] = hi - lo;
  }
  const double largest = *std::max_element(size.begin(), size.end());
  for (int k = 0; k < kz; ++k) {
    const auto support =
        strength_parts(deformation_per_vertex(decoded.features.row(k).data(), V, ref),
                       io::Components{}.eps1)
            .support;
    if (support > 0.8 * V) ++s.wide;
    const auto ku = static_cast<std::size_t>(k);
    if (training.size() >= 3 && size[ku] > 0 && size[ku] >= 0.1 * largest &&
        range[ku] < 0.1 * size[ku])
      ++s.constant;
  }
  return s;
}

std::string format_diagnosis(const MsaeDiagnosis& d, const std::string& heldout_part) {
  std::string t = fmt::format(
      "MSAE diagnosis: {} training shapes (PCA spans {} direction(s)), {} {} shapes\n"
      "  |C_k|: the component's weights; inside: share of |C_k|^2 within Omega's radius of its "
      "centre;\n"
      "  support: vertices whose decoded deformation reaches 10% of its peak; strength: eq. 7, "
      "the\n"
      "  mean deformation over the vertices it moves by more than eps1 = {:g} ('counted', of the "
      "mesh's\n"
      "  {}); on support: the same mean over the support's vertices only;\n"
      "  codes: range over the training shapes; share: mean part of its block's deformation of "
      "the\n"
      "  {} shapes.\n",
      d.n_training, d.pca_rank, d.n_heldout, heldout_part, d.eps1, d.n_vertices, heldout_part);
  for (const auto& level : d.levels) {
    t += fmt::format(
        "\n"
        "level {}: {} components, {} distinct centres; decoded directions' effective rank {} "
        "(singular values / largest: {:.3f})\n",
        level.level, level.components.size(), level.distinct_centres, level.effective_rank,
        fmt::join(level.singular_values, " "));
    t += fmt::format("  {:>5} {:>3} {:>6} {:>7} {:>6} {:>7} {:>8} {:>7} {:>10} {:>19} {:>6}\n",
                     "block", "k", "centre", "|C_k|", "inside", "support", "strength", "counted",
                     "on support", "codes", "share");
    for (const auto& c : level.components)
      t += fmt::format(
          "  {:>5} {:>3} {:>6} {:>7.3f} {:>6} {:>7} {:>8.4f} {:>7} {:>10.4f} {:>9.3g}..{:<9.3g} "
          "{:>5.1f}%\n",
          c.block, c.k, c.centre, c.weight_norm,
          c.inside < 0 ? std::string("-") : fmt::format("{:.2f}", c.inside), c.eq7.support,
          c.eq7.strength, c.eq7.counted, c.eq7.support_strength, c.code_min, c.code_max,
          100 * c.share);
    if (level.components.empty()) continue;
    std::vector<int> counted;
    int pass = 0, pass_support = 0;
    for (const auto& c : level.components) {
      counted.push_back(c.eq7.counted);
      pass += c.eq7.strength >= d.eps2 ? 1 : 0;
      pass_support += c.eq7.support_strength >= d.eps2 ? 1 : 0;
    }
    std::nth_element(counted.begin(),
                     counted.begin() + static_cast<std::ptrdiff_t>(counted.size() / 2),
                     counted.end());
    t += fmt::format(
        "  eq. 7 counts a median {} of {} vertices; {} of {} reach eps2 = {:g} (the pruning "
        "threshold), {} over their support only\n",
        counted[counted.size() / 2], d.n_vertices, pass, level.components.size(), d.eps2,
        pass_support);
  }
  if (d.second.children > 0) {
    const auto& s = d.second;
    t += fmt::format(
        "\n"
        "level 1 on the training shapes' residual R after level 0 (shares of its energy):\n"
        "  fed to its {} autoencoder(s) ({} components){}: {:.1f}%\n"
        "  left by the trained level 1: {:.1f}%\n"
        "  left by the best linear autoencoders of the same sizes on the same inputs: {:.1f}%\n"
        "  left by one linear autoencoder on R whole: {:.1f}% with {} components, {:.1f}% with "
        "{}\n",
        s.children, s.components, s.children > 1 ? " through the attention masks" : "", 100 * s.fed,
        100 * s.left_trained, 100 * s.left_linear, 100 * s.left_one, s.components,
        100 * s.left_one_child, s.child_kz);
    if (s.heldout_whole >= 0)
      t += fmt::format(
          "  on the {} shapes, through the encoders (shares of their residual after level 0, "
          "{:.3g} per shape):\n"
          "    the children's own errors sum to {:.1f}% (what their losses see); the shapes are "
          "left with\n"
          "    {:.1f}%, the cross terms between the children's errors adding {:+.1f}%\n",
          heldout_part, s.heldout_residual, 100 * s.heldout_own, 100 * s.heldout_whole,
          100 * (s.heldout_whole - s.heldout_own));
  }
  return t;
}

}  // namespace df::models
