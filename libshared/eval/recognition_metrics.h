// Measures of generated actions in a recogniser's feature space, as Action2Motion (Guo et al.
// 2020), ACTOR (Petrovich et al. 2021) and MDM (Tevet et al. 2023) report them beside MMD:
//   FID            Fréchet distance between Gaussians fitted to two sets of features:
//                  |mu_a - mu_b|^2 + tr(S_a + S_b - 2 (S_a S_b)^(1/2)) (covariances over n - 1)
//   diversity      the mean feature distance of 200 pairs drawn at random from all the clips
//   multimodality  per class, the mean feature distance of 20 pairs drawn within the class,
//                  averaged over the classes
//   accuracy       the share of clips whose most probable class under the recogniser is theirs
// Pairs are drawn as those papers' code draws them: both indices independent and uniform (a pair
// may be one clip twice). The value here is the mean over `draws` independent draws (each of 200
// or 20 pairs per class): the same expected value as one draw, with less sampling noise.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace df::eval {

/// Clips as a recogniser sees them: one row of features per clip, each clip's class (an index
/// into the recogniser's classes) and the class it finds most probable.
struct RecognisedClips {
  Eigen::MatrixXd features;
  std::vector<int> labels, predicted;
};

/// FID between the rows of A and of B (each at least 2 rows, the same columns).
double frechet_distance(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B);

/// The mean distance between rows first[k] and second[k] of F.
double mean_pair_distance(const Eigen::MatrixXd& F, const std::vector<std::size_t>& first,
                          const std::vector<std::size_t>& second);

/// Diversity of the rows of F: `pairs` random pairs per draw, the mean over `draws` draws.
double diversity(const Eigen::MatrixXd& F, std::uint64_t seed, int pairs = 200, int draws = 10);

/// Multimodality: per class with at least 2 clips, `pairs` random pairs within it per draw; the
/// mean over those classes and `draws` draws. NaN when no class has 2 clips.
double multimodality(const Eigen::MatrixXd& F, const std::vector<int>& labels, std::uint64_t seed,
                     int pairs = 20, int draws = 10);

/// The share of clips with predicted == label (NaN for none).
double accuracy(const RecognisedClips& c);

struct RecognitionScores {
  double fid = 0, diversity = 0, multimodality = 0, accuracy = 0;
};

struct RecognitionMetrics {
  std::size_t features = 0;     ///< width of the feature vectors
  RecognitionScores generated;  ///< fid: generated against real
  /// The real clips' own values (the reference row); fid: their even-numbered clips against the
  /// odd-numbered ones (the sampling noise of FID at half that many clips)
  RecognitionScores real;
};

/// Every measure of `generated` against `real` (and of `real` alone); draws from `seed`.
RecognitionMetrics recognition_metrics(const RecognisedClips& generated,
                                       const RecognisedClips& real, std::uint64_t seed = 1);

}  // namespace df::eval
