#include "models/msae/components.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "io/file_header.h"
#include "io/schema.h"
#include "models/msae/data.h"

namespace df::models {

using Eigen::Index;

std::vector<double> deformation_per_vertex(const float* x, int n_vertices,
                                           const std::array<double, 9>& reference) {
  std::vector<double> out(static_cast<std::size_t>(n_vertices));
  for (int i = 0; i < n_vertices; ++i) {
    double sq = 0;
    for (int d = 0; d < 9; ++d) {
      const double diff =
          static_cast<double>(x[9 * i + d]) - reference[static_cast<std::size_t>(d)];
      sq += diff * diff;
    }
    out[static_cast<std::size_t>(i)] = std::sqrt(sq);
  }
  return out;
}

StrengthParts strength_parts(const std::vector<double>& d, double eps1) {
  StrengthParts p;
  const double peak = d.empty() ? 0.0 : *std::max_element(d.begin(), d.end());
  double counted_sum = 0, support_sum = 0;
  for (double v : d) {
    if (v > eps1) counted_sum += v, ++p.counted;
    if (peak > 0 && v >= 0.1 * peak) support_sum += v, ++p.support;
  }
  p.strength = p.counted ? counted_sum / p.counted : 0.0;
  p.support_strength = p.support ? support_sum / p.support : 0.0;
  return p;
}

double component_strength(const float* x, int n_vertices, const std::array<double, 9>& reference,
                          double eps1) {
  return strength_parts(deformation_per_vertex(x, n_vertices, reference), eps1).strength;
}

std::vector<nn::Matrix<float>> block_codes(const MsaeNet<float>& net, const nn::Matrix<float>& data,
                                           const std::vector<std::int64_t>& rows, int levels) {
  const int through = levels > 0 ? levels : net.config().levels();
  const auto n = static_cast<Index>(rows.size());
  std::vector<nn::Matrix<float>> codes(net.blocks().size());
  for (std::size_t b = 0; b < codes.size(); ++b)
    if (net.blocks()[b].level < through) codes[b].resize(n, net.blocks()[b].kz);
  nn::Matrix<float> chunk;
  for (Index r = 0; r < n; r += 64) {
    const Index m = std::min<Index>(64, n - r);
    chunk.resize(m, data.cols());
    for (Index i = 0; i < m; ++i) chunk.row(i) = data.row(rows[static_cast<std::size_t>(r + i)]);
    std::vector<nn::Matrix<float>> part;
    net.reconstruct(chunk, through, &part);
    for (std::size_t b = 0; b < codes.size(); ++b)
      if (codes[b].size()) codes[b].middleRows(r, m) = part[b];
  }
  return codes;
}

std::vector<nn::Matrix<float>> block_codes(const MsaeNet<float>& net,
                                           const nn::Matrix<float>& shapes) {
  std::vector<std::int64_t> all(static_cast<std::size_t>(shapes.rows()));
  std::iota(all.begin(), all.end(), std::int64_t{0});
  return block_codes(net, shapes, all, 0);
}

void decode_block(const MsaeNet<float>& net, int b, const nn::Matrix<float>& codes,
                  const std::vector<int>& centres, const std::array<double, 9>& ref, double eps1,
                  ComponentLevel& out) {
  const int kz = net.blocks()[static_cast<std::size_t>(b)].kz, V = net.n_vertices();
  const nn::Matrix<float> zero = net.decode(b, nn::Matrix<float>::Zero(1, kz));
  nn::Matrix<float> z = nn::Matrix<float>::Zero(2 * kz, kz);
  for (int k = 0; k < kz; ++k) {
    z(2 * k, k) = codes.rows() ? codes.col(k).maxCoeff() : 1.0f;
    z(2 * k + 1, k) = codes.rows() ? codes.col(k).minCoeff() : -1.0f;
  }
  nn::Matrix<float> x = net.decode(b, z);
  for (Index r = 0; r < x.rows(); ++r)
    for (Index j = 0; j < x.cols(); ++j)
      x(r, j) += static_cast<float>(ref[static_cast<std::size_t>(j % 9)]) - zero(0, j);
  for (int k = 0; k < kz; ++k) {
    const double plus = component_strength(x.row(2 * k).data(), V, ref, eps1);
    const double minus = component_strength(x.row(2 * k + 1).data(), V, ref, eps1);
    const int pick = minus > plus ? 2 * k + 1 : 2 * k;
    const Index row = out.features.rows();
    out.features.conservativeResize(row + 1, x.cols());
    out.features.row(row) = x.row(pick);
    out.strength.push_back(std::max(plus, minus));
    out.center.push_back(centres[static_cast<std::size_t>(k)]);
    out.block.push_back(b);
    out.code.push_back(static_cast<double>(z(pick, k)));
    out.kept.push_back(1);
  }
}

nn::Matrix<double> level0_similarity(const ComponentLevel& level0,
                                     const std::array<double, 9>& ref) {
  nn::Matrix<double> d = level0.features.cast<double>();
  for (Index j = 0; j < d.cols(); ++j) d.col(j).array() -= ref[static_cast<std::size_t>(j % 9)];
  const Eigen::VectorXd norm = d.rowwise().norm();
  nn::Matrix<double> s = d * d.transpose();
  for (Index a = 0; a < s.rows(); ++a)
    for (Index b = 0; b < s.cols(); ++b) {
      const double n = norm[a] * norm[b];
      s(a, b) = n > 0 ? std::abs(s(a, b)) / n : 0.0;
    }
  return s;
}

Components extract_components(const MsaeModel& m, const std::vector<nn::Matrix<float>>& codes) {
  const MsaeNet<float>& net = *m.net;
  Components c;
  c.tmpl = m.tmpl;
  c.normalization = m.normalization;
  c.history = m.history;
  const auto ref = geometry::identity_features(&m.normalization);
  c.levels.resize(static_cast<std::size_t>(net.config().levels()));
  const auto centres = net.centres();
  for (std::size_t b = 0; b < net.blocks().size(); ++b)
    decode_block(net, static_cast<int>(b), codes[b], centres[b], ref, c.eps1,
                 c.levels[static_cast<std::size_t>(net.blocks()[b].level)]);
  c.attention = net.attention_masks(0);
  c.similarity = level0_similarity(c.levels[0], ref);
  return c;
}

void prune_components(Components& c, double eps1, double eps2) {
  if (!(eps1 >= 0) || !(eps2 >= 0)) throw UsageError("--eps1 and --eps2 must not be negative");
  const auto ref = geometry::identity_features(&c.normalization);
  const int V = static_cast<int>(c.tmpl.vertices.rows());
  for (auto& level : c.levels)
    for (Index k = 0; k < level.features.rows(); ++k) {
      level.strength[static_cast<std::size_t>(k)] =
          component_strength(level.features.row(k).data(), V, ref, eps1);
      level.kept[static_cast<std::size_t>(k)] =
          level.strength[static_cast<std::size_t>(k)] >= eps2 ? 1 : 0;
    }
  c.eps1 = eps1;
  c.eps2 = eps2;
}

}  // namespace df::models
