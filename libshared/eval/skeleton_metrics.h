// Metrics of generated skeleton actions against real ones (paper 3, SPEC §9):
//   MMD_u^2  the unbiased estimator of Gretton et al. with a Gaussian kernel
//            k(a, b) = exp(-|a - b|^2 / (2 s^2)), maximised over s = 1e-4, 1e-3, ..., 1e9
//   MMD_avg  per class j and frame index i: MMD_u^2 of the generated frames i against the real
//            test frames i, averaged over frames and classes
//   MMD_seq  per class: MMD_u^2 of whole sequences (flattened), averaged over classes
//   MMD_motion_avg, MMD_motion_seq  the same two of the frame differences x_{t+1} - x_t (not in
//            the paper): the paper's two barely see motion — real clips with their frames
//            shuffled in time, or with the first frame held still, score about as the clips
//            themselves — while these tell them apart by an order of magnitude
//   spread   per class: mean and standard deviation of the distance of each generated sequence
//            to the class's mean sequence (paper Table 4's diversity statistic)
//   variety  per class, of the generated and of the real sequences alike: the mean distance
//            between two sequences (flattened, in TRUTH's normalized coordinates) and MMD_seq
//            between the even- and the odd-numbered halves of the set at the bandwidth where the
//            class's MMD_seq peaked (the sampling noise of MMD_seq at that many sequences);
//            generated clips as varied as the real ones have a distance ratio near 1
//   pace     per class, of the generated and of the real sequences alike: the mean distance a
//            pose moves from one frame to the next; generated clips that move at the data's
//            pace have a ratio near 1
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "io/skeleton_file.h"

namespace df::eval {

using RowMatrixF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The bandwidths s of the maximum: 1e-4 ... 1e9 (14 values).
const std::vector<double>& mmd_bandwidths();

struct MmdResult {
  double mmd2 = 0;       ///< the maximum over the bandwidths
  double bandwidth = 0;  ///< where it is reached
};

/// MMD_u^2 between the rows of X (m samples) and of Y (n samples), m, n >= 2, same columns,
/// maximised over `bandwidths` (by default mmd_bandwidths()).
/// Squared distances from one Gram matrix (float GEMM in row blocks, in parallel); exponentials
/// only where a bandwidth makes them neither all 0 nor all within 1e-7 of 1 (there a second-order
/// expansion is exact to float precision). Deterministic: the same at any thread count.
MmdResult mmd2_max(const RowMatrixF& X, const RowMatrixF& Y,
                   const std::vector<double>& bandwidths = mmd_bandwidths());

/// The same in double with the brute-force double sum over every pair (tests' reference).
MmdResult mmd2_max_reference(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y);

struct ClassSkeletonMetrics {
  std::string name;
  std::size_t generated = 0, real = 0;  ///< sequences compared
  double mmd_avg = 0, mmd_seq = 0;
  double mmd_motion_avg = 0,
         mmd_motion_seq = 0;              ///< of frame differences (NaN for 1-frame sequences)
  double spread_mean = 0, spread_sd = 0;  ///< distance of generated sequences to their mean
  double pairwise_generated = 0, pairwise_real = 0;  ///< mean distance between two sequences
  double halves_generated = 0,
         halves_real = 0;  ///< MMD_seq of one half against the other (NaN below 4)
  double motion_generated = 0,
         motion_real = 0;  ///< mean distance a pose moves per frame (NaN for 1-frame sequences)
};

struct SkeletonMetrics {
  std::size_t frames = 0;  ///< frames compared per sequence (the shortest of both files)
  std::vector<ClassSkeletonMetrics> classes;
  double mmd_avg = 0, mmd_seq = 0;  ///< averages over the classes both files have
  double mmd_motion_avg = 0, mmd_motion_seq = 0;
  double pairwise_ratio = 0;  ///< mean over the classes of pairwise_generated / pairwise_real
  double pace_ratio = 0;      ///< mean over the classes of motion_generated / motion_real
};

/// The mean Euclidean distance between two different rows of X (double sums; 0 below 2 rows).
double mean_pairwise_distance(const RowMatrixF& X);

/// MMD_u^2 at bandwidth s between the even- and the odd-numbered rows of X (at one bandwidth:
/// maximised over all, two halves of one sample score 0 at the widest); NaN below 4 rows.
double halves_mmd(const RowMatrixF& X, double s);

/// One class's measures of generated sequences X against real ones Y (one flattened sequence per
/// row, `frame_size` values per frame): MMD_seq, MMD_avg, their motion forms, spread, variety.
ClassSkeletonMetrics skeleton_class_metrics(const RowMatrixF& X, const RowMatrixF& Y,
                                            std::size_t frame_size);

/// Which sequences of the two files are compared.
struct SkeletonSelection {
  bool all_truth = false;  ///< all of TRUTH's sequences, not only its test part
  std::vector<std::int32_t>
      pred_subjects;  ///< only PRED's sequences of these subjects (empty: all)
  /// only TRUTH's sequences of these subjects, in its test part or not (empty: its test part)
  std::vector<std::int32_t> truth_subjects;
};

/// The sequences compared: per class name both files have (in PRED's class order), PRED's and
/// TRUTH's sequences as `select` picks them (below), and the frames compared of each.
struct SkeletonPairing {
  struct Class {
    std::string name;
    std::vector<std::size_t> pred, truth;  ///< sequence indices in each file
  };
  std::size_t frames = 0;  ///< the shortest selected sequence of both files
  std::vector<Class> classes;
};

/// Which sequences skeleton_metrics compares (InvalidInput when the skeletons differ).
SkeletonPairing pair_skeleton_classes(const io::SkeletonFile& pred, const io::SkeletonFile& truth,
                                      const SkeletonSelection& select = {});

/// PRED's sequences against TRUTH's of the same class name, as `select` picks them (by default
/// all of PRED's and TRUTH's test sequences when it marks any), both in TRUTH's coordinates (PRED
/// converted through raw coordinates when its normalization differs), cut to the shortest
/// sequence. Subjects are read from /sequences/subjects: InvalidInput when a file has none or a
/// named subject performs none of its sequences. The subject lists let the data be measured
/// against itself — the training subjects' clips against held-out ones give the score of a
/// generator that reproduced its training data exactly.
SkeletonMetrics skeleton_metrics(const io::SkeletonFile& pred, const io::SkeletonFile& truth,
                                 const SkeletonSelection& select = {});

}  // namespace df::eval
