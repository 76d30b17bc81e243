// Sequences from a trained ActGAN for a class or a soft mixture of classes (the generator's label
// input y = (p_1, ..., p_C)), and the trained classifier applied to any skeleton file of the same
// skeleton: what gen-actgan and classify-actions run (their jobs: apps/gen_actgan,
// apps/classify_actions).
#pragma once

#include <string>
#include <vector>

#include "core/common_options.h"
#include "io/skeleton_file.h"
#include "models/actgan/model.h"

namespace df::models {

struct ActganGenerateOptions {
  std::string model, output;
  std::vector<std::string> classes;  ///< classes to generate (empty and no mix: every class)
  std::string mix;                   ///< "walk:0.5,wave:0.5": one soft mixture instead
  int count = 10;                    ///< sequences per class (or of the mixture)
  int length = 0;                    ///< frames per sequence (0: the training clips' length)
  std::string latents;               ///< "" or a TSV of the latent trajectories
};

/// The label vectors of the requested sequences: one-hot rows per class, or the mixture's
/// weights (normalized to sum 1); `names` gets each row's name (class or "a+b").
nn::Matrix<float> label_rows(const ActganModel& m, const ActganGenerateOptions& opt,
                             std::vector<std::string>& names);

/// Generates one sequence per row of `y` (h_1 and the noise drawn from rng in a fixed order);
/// returns poses [rows, length, P] and latents [rows, length, Z].
void generate_actions(const ActganModel& m, const nn::Matrix<float>& y, int length, Rng& rng,
                      std::vector<float>& poses, std::vector<float>& latents);

/// The column of row r's largest value (the first of equals): a probability row's most probable
/// class, a label row's strongest class.
Eigen::Index most_probable(const nn::Matrix<float>& p, Eigen::Index r);

/// What the model's classifier makes of sequences: class probabilities and the features its
/// output layer reads (the head's hidden layer, m.config.fc wide).
struct Recognised {
  nn::Matrix<float> prob;      ///< [sequences, C]
  nn::Matrix<float> features;  ///< [sequences, fc]
};

/// The classifier on the sequences `seqs` of `s` (the same skeleton; poses brought into the
/// model's coordinates), each read for its first `length` frames (0: each batch of 64 to its
/// shortest sequence). The model must have a classifier (callers check, naming its file).
Recognised recognise(const ActganModel& m, const io::SkeletonFile& s,
                     const std::vector<std::size_t>& seqs, std::size_t length = 0);

}  // namespace df::models
