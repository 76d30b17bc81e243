#include "eval/skeleton_metrics.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/log.h"
#include "core/rng.h"

namespace df::eval {
namespace {

constexpr Eigen::Index kBlock =
    128;  // rows per parallel task (fixed: results do not depend on threads)

enum Pair { kXX = 0, kYY = 1, kXY = 2 };

// The squared distances between the rows of A and B (only the lower triangle, j < i, when
// `lower`: A = B), from the product A B^T in D and the rows' squared norms.
void to_squared_distances(RowMatrixF& D, const Eigen::VectorXf& na, const Eigen::VectorXf& nb,
                          bool lower, Eigen::Index r0, Eigen::Index rows) {
  for (Eigen::Index i = r0; i < r0 + rows; ++i) {
    const Eigen::Index cols = lower ? i : D.cols();
    for (Eigen::Index j = 0; j < cols; ++j) D(i, j) = std::max(0.0f, na[i] + nb[j] - 2 * D(i, j));
  }
}

// The three distance matrices of MMD: X-X and Y-Y (lower triangles) and X-Y.
struct Distances {
  RowMatrixF xx, yy, xy;
};

// Four GEMM tasks of similar size (X X^T and Y Y^T lower triangles, the two halves of X Y^T);
// each entry is computed by one task, so the result is the same at any thread count.
Distances squared_distances(const RowMatrixF& X, const RowMatrixF& Y) {
  Distances d{RowMatrixF(X.rows(), X.rows()), RowMatrixF(Y.rows(), Y.rows()),
              RowMatrixF(X.rows(), Y.rows())};
  const Eigen::VectorXf nx = X.rowwise().squaredNorm(), ny = Y.rowwise().squaredNorm();
  const Eigen::Index half = X.rows() / 2;
  tbb::parallel_for(0, 4, [&](int task) {
    if (task == 0) {
      d.xx.triangularView<Eigen::StrictlyLower>() = X * X.transpose();
      to_squared_distances(d.xx, nx, nx, true, 0, X.rows());
    } else if (task == 1) {
      d.yy.triangularView<Eigen::StrictlyLower>() = Y * Y.transpose();
      to_squared_distances(d.yy, ny, ny, true, 0, Y.rows());
    } else {
      const Eigen::Index r0 = task == 2 ? 0 : half, rows = task == 2 ? half : X.rows() - half;
      d.xy.middleRows(r0, rows).noalias() = X.middleRows(r0, rows) * Y.transpose();
      to_squared_distances(d.xy, nx, ny, false, r0, rows);
    }
  });
  return d;
}

// The range, sum and sum of squares of D's entries (its strict lower triangle when `lower`) in
// one pass: rows in fixed blocks, the blocks' results combined in order.
struct DistanceStats {
  double min = std::numeric_limits<double>::infinity(), max = 0, sum = 0, sum_squares = 0;
};
DistanceStats distance_stats(const RowMatrixF& D, bool lower) {
  const Eigen::Index N = D.rows(), blocks = (N + kBlock - 1) / kBlock;
  std::vector<DistanceStats> partial(static_cast<std::size_t>(blocks));
  tbb::parallel_for(Eigen::Index{0}, blocks, [&](Eigen::Index b) {
    DistanceStats& st = partial[static_cast<std::size_t>(b)];
    for (Eigen::Index i = b * kBlock; i < std::min(N, (b + 1) * kBlock); ++i) {
      const Eigen::Index cols = lower ? i : D.cols();
      if (cols == 0) continue;
      const auto row = D.row(i).head(cols);
      st.min = std::min(st.min, static_cast<double>(row.minCoeff()));
      st.max = std::max(st.max, static_cast<double>(row.maxCoeff()));
      st.sum += row.template cast<double>().sum();
      st.sum_squares += row.template cast<double>().squaredNorm();
    }
  });
  DistanceStats total;
  for (const auto& p : partial) {
    total.min = std::min(total.min, p.min);
    total.max = std::max(total.max, p.max);
    total.sum += p.sum;
    total.sum_squares += p.sum_squares;
  }
  return total;
}

// The sum over D's entries (its strict lower triangle when `lower`) of f(row segment): rows in
// fixed blocks, the blocks' sums added in order.
template <class F>
double sum_rows(const RowMatrixF& D, bool lower, F&& f) {
  const Eigen::Index N = D.rows(), blocks = (N + kBlock - 1) / kBlock;
  std::vector<double> partial(static_cast<std::size_t>(blocks), 0.0);
  tbb::parallel_for(Eigen::Index{0}, blocks, [&](Eigen::Index b) {
    double s = 0;
    for (Eigen::Index i = b * kBlock; i < std::min(N, (b + 1) * kBlock); ++i) {
      const Eigen::Index cols = lower ? i : D.cols();
      if (cols > 0) s += f(D.row(i).head(cols));
    }
    partial[static_cast<std::size_t>(b)] = s;
  });
  double total = 0;
  for (double p : partial) total += p;
  return total;
}

void check_samples(Eigen::Index m, Eigen::Index n, Eigen::Index dx, Eigen::Index dy) {
  if (m < 2 || n < 2)
    throw InvalidInput(fmt::format("MMD needs at least 2 samples on each side ({} and {})", m, n));
  if (dx != dy) throw InvalidInput(fmt::format("MMD of samples of {} and {} values", dx, dy));
}

}  // namespace

const std::vector<double>& mmd_bandwidths() {
  static const std::vector<double> s{1e-4, 1e-3, 1e-2, 1e-1, 1,   1e1, 1e2,
                                     1e3,  1e4,  1e5,  1e6,  1e7, 1e8, 1e9};
  return s;
}

MmdResult mmd2_max(const RowMatrixF& X, const RowMatrixF& Y,
                   const std::vector<double>& bandwidths) {
  check_samples(X.rows(), Y.rows(), X.cols(), Y.cols());
  const Distances d = squared_distances(X, Y);
  const std::array<const RowMatrixF*, 3> D{&d.xx, &d.yy, &d.xy};
  const std::array<bool, 3> lower{true, true, false};
  // The range of the distances, and the sums of D and D^2 for bandwidths so wide that
  // exp(-g D) = 1 - g D + (g D)^2 / 2 to float precision.
  double dmin = std::numeric_limits<double>::infinity(), dmax = 0;
  std::array<double, 3> s1{}, s2{};
  for (std::size_t c = 0; c < 3; ++c) {
    const DistanceStats st = distance_stats(*D[c], lower[c]);
    dmin = std::min(dmin, st.min);
    dmax = std::max(dmax, st.max);
    s1[c] = st.sum;
    s2[c] = st.sum_squares;
  }
  const double m = static_cast<double>(X.rows()), n = static_cast<double>(Y.rows());
  const std::array<double, 3> pairs{m * (m - 1) / 2, n * (n - 1) / 2, m * n};
  MmdResult best{-std::numeric_limits<double>::infinity(), 0};
  for (double s : bandwidths) {
    const double g = 1 / (2 * s * s);
    std::array<double, 3> k{0, 0, 0};
    if (g * dmin > 700) {
      // every kernel value below 1e-304: the estimate is 0
    } else if (g * dmax < 1e-4) {
      for (std::size_t c = 0; c < 3; ++c) k[c] = pairs[c] - g * s1[c] + g * g / 2 * s2[c];
    } else {
      const auto gf = static_cast<float>(g);
      for (std::size_t c = 0; c < 3; ++c)
        k[c] = sum_rows(*D[c], lower[c], [gf](const auto& r) {
          return static_cast<double>((r.array() * -gf).exp().sum());
        });
    }
    // X-X and Y-Y pairs appear once in a lower triangle, twice in sum_{i != j}
    const double v = 2 * k[kXX] / (m * (m - 1)) + 2 * k[kYY] / (n * (n - 1)) - 2 * k[kXY] / (m * n);
    if (v > best.mmd2) best = {v, s};
  }
  return best;
}

MmdResult mmd2_max_reference(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y) {
  check_samples(X.rows(), Y.rows(), X.cols(), Y.cols());
  const double m = static_cast<double>(X.rows()), n = static_cast<double>(Y.rows());
  MmdResult best{-std::numeric_limits<double>::infinity(), 0};
  for (double s : mmd_bandwidths()) {
    const auto k = [&](const auto& a, const auto& b) {
      return std::exp(-(a - b).squaredNorm() / (2 * s * s));
    };
    double xx = 0, yy = 0, xy = 0;
    for (Eigen::Index i = 0; i < X.rows(); ++i)
      for (Eigen::Index j = 0; j < X.rows(); ++j)
        if (i != j) xx += k(X.row(i), X.row(j));
    for (Eigen::Index i = 0; i < Y.rows(); ++i)
      for (Eigen::Index j = 0; j < Y.rows(); ++j)
        if (i != j) yy += k(Y.row(i), Y.row(j));
    for (Eigen::Index i = 0; i < X.rows(); ++i)
      for (Eigen::Index j = 0; j < Y.rows(); ++j) xy += k(X.row(i), Y.row(j));
    const double v = xx / (m * (m - 1)) + yy / (n * (n - 1)) - 2 * xy / (m * n);
    if (v > best.mmd2) best = {v, s};
  }
  return best;
}

double mean_pairwise_distance(const RowMatrixF& X) {
  const Eigen::Index n = X.rows();
  if (n < 2) return 0;
  const Eigen::MatrixXd D = X.cast<double>();
  double sum = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i + 1; j < n; ++j) sum += (D.row(i) - D.row(j)).norm();
  return sum / (static_cast<double>(n) * static_cast<double>(n - 1) / 2);
}

double halves_mmd(const RowMatrixF& X, double s) {
  if (X.rows() < 4) return std::numeric_limits<double>::quiet_NaN();
  RowMatrixF even((X.rows() + 1) / 2, X.cols()), odd(X.rows() / 2, X.cols());
  for (Eigen::Index r = 0; r < X.rows(); ++r) (r % 2 ? odd.row(r / 2) : even.row(r / 2)) = X.row(r);
  return mmd2_max(even, odd, {s}).mmd2;
}

namespace {

// The first `frames` frames of the listed sequences, one row per sequence.
RowMatrixF sequence_rows(const io::SkeletonFile& f, const std::vector<float>& poses,
                         const std::vector<std::size_t>& seqs, std::size_t frames) {
  const std::size_t fs = f.frame_size();
  RowMatrixF M(static_cast<Eigen::Index>(seqs.size()), static_cast<Eigen::Index>(frames * fs));
  for (std::size_t r = 0; r < seqs.size(); ++r)
    std::copy_n(poses.data() + static_cast<std::size_t>(f.offsets[seqs[r]]) * fs, frames * fs,
                M.row(static_cast<Eigen::Index>(r)).data());
  return M;
}

void spread(const RowMatrixF& seqs, double& mean, double& sd) {
  const Eigen::RowVectorXf centre = seqs.colwise().mean();
  std::vector<double> d(static_cast<std::size_t>(seqs.rows()));
  for (Eigen::Index r = 0; r < seqs.rows(); ++r)
    d[static_cast<std::size_t>(r)] = (seqs.row(r) - centre).norm();
  mean = 0;
  for (double x : d) mean += x / static_cast<double>(d.size());
  sd = 0;
  for (double x : d) sd += (x - mean) * (x - mean) / static_cast<double>(d.size());
  sd = std::sqrt(sd);
}

// The differences of consecutive frames x_{t+1} - x_t of each row (one flattened sequence of
// `frame_size` values per frame): rows of frames - 1 velocities.
RowMatrixF frame_differences(const RowMatrixF& M, std::size_t frame_size) {
  const auto cols = static_cast<Eigen::Index>(frame_size);
  return M.rightCols(M.cols() - cols) - M.leftCols(M.cols() - cols);
}

// The mean over rows and frames of the distance a pose moves from one frame to the next (NaN for
// one frame).
double mean_frame_motion(const RowMatrixF& M, std::size_t frame_size) {
  if (M.cols() <= static_cast<Eigen::Index>(frame_size) || M.rows() == 0)
    return std::numeric_limits<double>::quiet_NaN();
  const RowMatrixF D = frame_differences(M, frame_size);
  const auto cols = static_cast<Eigen::Index>(frame_size);
  double sum = 0;
  for (Eigen::Index r = 0; r < D.rows(); ++r)
    for (Eigen::Index t = 0; t < D.cols() / cols; ++t)
      sum += D.row(r).segment(t * cols, cols).cast<double>().norm();
  return sum / static_cast<double>(D.rows() * (D.cols() / cols));
}

// MMD_seq (whole rows) and MMD_avg (per frame index, averaged) of X against Y; the bandwidth of
// MMD_seq's maximum.
double mmd_seq_avg(const RowMatrixF& X, const RowMatrixF& Y, std::size_t frame_size, double& seq,
                   double& avg) {
  const MmdResult whole = mmd2_max(X, Y);
  seq = whole.mmd2;
  const auto cols = static_cast<Eigen::Index>(frame_size);
  const Eigen::Index frames = X.cols() / cols;
  avg = 0;
  for (Eigen::Index t = 0; t < frames; ++t)
    avg += mmd2_max(X.middleCols(t * cols, cols), Y.middleCols(t * cols, cols)).mmd2 /
           static_cast<double>(frames);
  return whole.bandwidth;
}

// Per sequence of `f` (named `what` in errors): 1 when its subject is one of `subjects`.
std::vector<char> of_subjects(const io::SkeletonFile& f, const std::vector<std::int32_t>& subjects,
                              const char* what) {
  if (f.subjects.size() != f.sequences())
    throw InvalidInput(fmt::format(
        "{} names no subjects (/sequences/subjects): it cannot be selected by subject", what));
  std::vector<char> in(f.sequences(), 0);
  for (const auto v : subjects) {
    bool found = false;
    for (std::size_t s = 0; s < f.sequences(); ++s)
      if (f.subjects[s] == v) in[s] = 1, found = true;
    if (!found)
      throw InvalidInput(fmt::format("subject {} performs none of {}'s sequences", v, what));
  }
  return in;
}

}  // namespace

// One class's MMD_seq, MMD_avg, the same of frame differences, and spread: generated sequences X
// against real ones Y, one flattened sequence per row, `frame_size` values per frame.
ClassSkeletonMetrics skeleton_class_metrics(const RowMatrixF& X, const RowMatrixF& Y,
                                            std::size_t frame_size) {
  ClassSkeletonMetrics m;
  m.generated = static_cast<std::size_t>(X.rows());
  m.real = static_cast<std::size_t>(Y.rows());
  const double seq_bandwidth = mmd_seq_avg(X, Y, frame_size, m.mmd_seq, m.mmd_avg);
  if (X.cols() > static_cast<Eigen::Index>(frame_size))
    mmd_seq_avg(frame_differences(X, frame_size), frame_differences(Y, frame_size), frame_size,
                m.mmd_motion_seq, m.mmd_motion_avg);
  else
    m.mmd_motion_seq = m.mmd_motion_avg =
        std::numeric_limits<double>::quiet_NaN();  // one frame: no motion
  spread(X, m.spread_mean, m.spread_sd);
  m.motion_generated = mean_frame_motion(X, frame_size);
  m.motion_real = mean_frame_motion(Y, frame_size);
  m.pairwise_generated = mean_pairwise_distance(X);
  m.pairwise_real = mean_pairwise_distance(Y);
  m.halves_generated = halves_mmd(X, seq_bandwidth);
  m.halves_real = halves_mmd(Y, seq_bandwidth);
  return m;
}

SkeletonPairing pair_skeleton_classes(const io::SkeletonFile& pred, const io::SkeletonFile& truth,
                                      const SkeletonSelection& select) {
  if (pred.joints != truth.joints || pred.dims != truth.dims)
    throw InvalidInput(fmt::format("PRED has {} joints x {}, TRUTH {} x {}", pred.joints, pred.dims,
                                   truth.joints, truth.dims));
  if (select.all_truth && !select.truth_subjects.empty())
    throw UsageError(
        "--all-truth or --truth-subjects: the first takes every TRUTH sequence, the second some");
  const std::vector<char> pred_in = select.pred_subjects.empty()
                                        ? std::vector<char>(pred.sequences(), 1)
                                        : of_subjects(pred, select.pred_subjects, "PRED");
  std::vector<char> truth_in(truth.sequences(), 1);
  if (!select.truth_subjects.empty())
    truth_in = of_subjects(truth, select.truth_subjects, "TRUTH");
  else if (!select.all_truth && std::count(truth.test.begin(), truth.test.end(), 1) > 0)
    for (std::size_t s = 0; s < truth.sequences(); ++s) truth_in[s] = truth.test[s] != 0;
  SkeletonPairing out;
  out.frames = std::numeric_limits<std::size_t>::max();
  for (std::size_t s = 0; s < pred.sequences(); ++s)
    if (pred_in[s]) out.frames = std::min(out.frames, pred.length(s));
  for (std::size_t s = 0; s < truth.sequences(); ++s)
    if (truth_in[s]) out.frames = std::min(out.frames, truth.length(s));
  for (std::size_t c = 0; c < pred.class_names.size(); ++c) {
    const auto tc =
        std::find(truth.class_names.begin(), truth.class_names.end(), pred.class_names[c]);
    if (tc == truth.class_names.end()) continue;
    SkeletonPairing::Class k;
    k.name = pred.class_names[c];
    for (std::size_t s = 0; s < pred.sequences(); ++s)
      if (pred_in[s] && pred.labels[s] == static_cast<std::int32_t>(c)) k.pred.push_back(s);
    for (std::size_t s = 0; s < truth.sequences(); ++s)
      if (truth_in[s] &&
          truth.labels[s] == static_cast<std::int32_t>(tc - truth.class_names.begin()))
        k.truth.push_back(s);
    out.classes.push_back(std::move(k));
  }
  return out;
}

SkeletonMetrics skeleton_metrics(const io::SkeletonFile& pred, const io::SkeletonFile& truth,
                                 const SkeletonSelection& select) {
  const SkeletonPairing pairs = pair_skeleton_classes(pred, truth, select);
  SkeletonMetrics out;
  out.frames = pairs.frames;
  const std::vector<float> pred_poses = io::poses_normalized_as(pred, truth.normalization);
  const std::size_t fs = pred.frame_size();
  for (const auto& k : pairs.classes) {
    if (k.pred.size() < 2 || k.truth.size() < 2) {
      log::warn("class {}: {} generated and {} real sequences; MMD needs 2 of each, skipped",
                k.name, k.pred.size(), k.truth.size());
      continue;
    }
    const RowMatrixF X = sequence_rows(pred, pred_poses, k.pred, out.frames);
    const RowMatrixF Y = sequence_rows(truth, truth.poses, k.truth, out.frames);
    ClassSkeletonMetrics m = skeleton_class_metrics(X, Y, fs);
    m.name = k.name;
    out.classes.push_back(m);
  }
  if (out.classes.empty())
    throw InvalidInput("PRED and TRUTH share no class with 2 sequences each");
  for (const auto& m : out.classes) {
    const auto n = static_cast<double>(out.classes.size());
    out.mmd_avg += m.mmd_avg / n;
    out.mmd_seq += m.mmd_seq / n;
    out.mmd_motion_avg += m.mmd_motion_avg / n;
    out.mmd_motion_seq += m.mmd_motion_seq / n;
    out.pairwise_ratio += m.pairwise_generated / m.pairwise_real / n;
    out.pace_ratio += m.motion_generated / m.motion_real / n;
  }
  return out;
}

}  // namespace df::eval
