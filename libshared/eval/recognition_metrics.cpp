#include "eval/recognition_metrics.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <map>

#include "core/error.h"
#include "core/rng.h"

namespace df::eval {
namespace {

struct Gaussian {
  Eigen::VectorXd mean;
  Eigen::MatrixXd cov;
};

Gaussian fit_gaussian(const Eigen::MatrixXd& X) {
  Gaussian g;
  g.mean = X.colwise().mean().transpose();
  const Eigen::MatrixXd centred = X.rowwise() - g.mean.transpose();
  g.cov = centred.transpose() * centred / static_cast<double>(X.rows() - 1);
  return g;
}

// The symmetric square root of a symmetric positive semi-definite matrix (negative eigenvalues
// from rounding taken as 0).
Eigen::MatrixXd psd_sqrt(const Eigen::MatrixXd& S) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S);
  const Eigen::VectorXd root = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return es.eigenvectors() * root.asDiagonal() * es.eigenvectors().transpose();
}

// Indices drawn uniformly from [0, n).
std::vector<std::size_t> draw_indices(std::size_t n, int count, Rng& rng) {
  std::vector<std::size_t> v(static_cast<std::size_t>(count));
  for (auto& i : v) i = static_cast<std::size_t>(rng.below(n));
  return v;
}

Eigen::MatrixXd rows_of(const Eigen::MatrixXd& F, std::size_t first, std::size_t step) {
  std::vector<Eigen::Index> idx;
  for (auto i = static_cast<Eigen::Index>(first); i < F.rows();
       i += static_cast<Eigen::Index>(step))
    idx.push_back(i);
  return F(idx, Eigen::all);
}

RecognitionScores scores_of(const RecognisedClips& c, std::uint64_t seed) {
  RecognitionScores s;
  s.diversity = diversity(c.features, seed);
  s.multimodality = multimodality(c.features, c.labels, seed + 1);
  s.accuracy = accuracy(c);
  return s;
}

void check_clips(const RecognisedClips& c, const char* what) {
  const auto n = static_cast<std::size_t>(c.features.rows());
  if (c.labels.size() != n || c.predicted.size() != n)
    throw Error(fmt::format("internal: {} clips have {} rows, {} labels, {} predictions", what, n,
                            c.labels.size(), c.predicted.size()));
}

}  // namespace

double frechet_distance(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  if (A.rows() < 2 || B.rows() < 2 || A.cols() != B.cols())
    throw InvalidInput(fmt::format(
        "FID needs at least 2 feature vectors of the same width on each side ({} x {}, {} x {})",
        A.rows(), A.cols(), B.rows(), B.cols()));
  const Gaussian a = fit_gaussian(A), b = fit_gaussian(B);
  // tr (S_a S_b)^(1/2) = tr (S_a^(1/2) S_b S_a^(1/2))^(1/2): the latter is symmetric PSD.
  const Eigen::MatrixXd ra = psd_sqrt(a.cov);
  const Eigen::MatrixXd inner = ra * b.cov * ra;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (inner + inner.transpose()),
                                                          Eigen::EigenvaluesOnly);
  const double cross = es.eigenvalues().cwiseMax(0.0).cwiseSqrt().sum();
  return (a.mean - b.mean).squaredNorm() + a.cov.trace() + b.cov.trace() - 2 * cross;
}

double mean_pair_distance(const Eigen::MatrixXd& F, const std::vector<std::size_t>& first,
                          const std::vector<std::size_t>& second) {
  if (first.size() != second.size() || first.empty())
    throw Error("internal: mean_pair_distance of unequal or empty index lists");
  double sum = 0;
  for (std::size_t k = 0; k < first.size(); ++k)
    sum +=
        (F.row(static_cast<Eigen::Index>(first[k])) - F.row(static_cast<Eigen::Index>(second[k])))
            .norm();
  return sum / static_cast<double>(first.size());
}

double diversity(const Eigen::MatrixXd& F, std::uint64_t seed, int pairs, int draws) {
  if (F.rows() < 2) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0;
  for (int d = 0; d < draws; ++d) {
    Rng rng(seed, static_cast<std::uint64_t>(d));
    const auto first = draw_indices(static_cast<std::size_t>(F.rows()), pairs, rng);
    const auto second = draw_indices(static_cast<std::size_t>(F.rows()), pairs, rng);
    sum += mean_pair_distance(F, first, second);
  }
  return sum / draws;
}

double multimodality(const Eigen::MatrixXd& F, const std::vector<int>& labels, std::uint64_t seed,
                     int pairs, int draws) {
  std::map<int, std::vector<std::size_t>> members;
  for (std::size_t i = 0; i < labels.size(); ++i) members[labels[i]].push_back(i);
  double sum = 0;
  int classes = 0;
  for (const auto& [label, idx] : members) {
    if (idx.size() < 2) continue;
    ++classes;
    for (int d = 0; d < draws; ++d) {
      Rng rng(seed, static_cast<std::uint64_t>(label) * 1000 + static_cast<std::uint64_t>(d));
      std::vector<std::size_t> first = draw_indices(idx.size(), pairs, rng),
                               second = draw_indices(idx.size(), pairs, rng);
      for (auto& i : first) i = idx[i];
      for (auto& i : second) i = idx[i];
      sum += mean_pair_distance(F, first, second) / draws;
    }
  }
  return classes ? sum / classes : std::numeric_limits<double>::quiet_NaN();
}

double accuracy(const RecognisedClips& c) {
  if (c.labels.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::size_t right = 0;
  for (std::size_t i = 0; i < c.labels.size(); ++i) right += c.labels[i] == c.predicted[i];
  return static_cast<double>(right) / static_cast<double>(c.labels.size());
}

RecognitionMetrics recognition_metrics(const RecognisedClips& generated,
                                       const RecognisedClips& real, std::uint64_t seed) {
  check_clips(generated, "generated");
  check_clips(real, "real");
  RecognitionMetrics m;
  m.features = static_cast<std::size_t>(real.features.cols());
  m.generated = scores_of(generated, seed);
  m.generated.fid = frechet_distance(generated.features, real.features);
  m.real = scores_of(real, seed);
  m.real.fid = real.features.rows() >= 4
                   ? frechet_distance(rows_of(real.features, 0, 2), rows_of(real.features, 1, 2))
                   : std::numeric_limits<double>::quiet_NaN();
  return m;
}

}  // namespace df::eval
