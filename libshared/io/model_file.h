// The model file kinds' layout (schemas/nn-checkpoint.json, extended by bdlstm-model,
// msae-model and actgan-model): the only place outside the data kinds' owners that names their
// groups and datasets. The parts every model kind shares are read and written here — the
// training state (/params, one or several Adam states, /rng, the iteration) and the training log
// (/training) — and the groups a single model kind adds are named here (model_layout), so that a
// reader in another language (or a schema change) finds the whole layout in one header. The
// template and /normalization of the mesh models are io/acap_file's; the classes, skeleton and
// pose normalization of the ActGAN model are io/skeleton_file's.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "io/h5.h"

namespace df::io {

namespace model_layout {
inline constexpr const char* config = "/config";  ///< each model's settings, as attributes
inline constexpr const char* params = "/params";  ///< one dataset per parameter
inline constexpr const char* rng = "/rng";
inline constexpr const char* training_log = "/training/log";
inline constexpr const char* split = "/split";        ///< bdlstm, msae: which frames trained
inline constexpr const char* geodesic = "/geodesic";  ///< msae: the geodesic distances it used
inline constexpr const char* validation_subjects = "/validation/subjects";  ///< actgan
/// "/split/<part>" (part: train, validation, test; bdlstm also sequences)
std::string split_part(const std::string& part);
/// "/geodesic/<name>" (sources, distances)
std::string geodesic_part(const std::string& name);
/// "/params/<name>"
std::string param(const std::string& name);
/// The Adam state of a model with one optimizer ("/optimizer", name empty) or of one of several
/// ("/optimizers/<name>", ActGAN's).
std::string optimizer(const std::string& name = {});
}  // namespace model_layout

// --- the training state

void write_iteration(h5::File& f, std::int64_t iteration);
std::int64_t read_iteration(const h5::File& f);

/// /params/<name>, a [rows, cols] float matrix.
template <class Derived>
void write_param(h5::File& f, const std::string& name, const Eigen::DenseBase<Derived>& value) {
  f.write_matrix(model_layout::param(name), value);
}
/// /params's `order`: the parameters' names in store order.
void write_param_order(h5::File& f, const std::vector<std::string>& names);
std::vector<std::string> read_param_order(const h5::File& f);
/// Reads /params/<name> and checks its shape: InvalidInput naming the dataset when it differs.
h5::RowMatrix<float> read_param(const h5::File& f, const std::string& name, Eigen::Index rows,
                                Eigen::Index cols);

struct AdamState {
  std::vector<float> m, v;  ///< first and second moments, flat in store order
  std::int64_t step = 0;
};
/// group: model_layout::optimizer(name)
void write_adam_state(h5::File& f, const std::string& group, std::span<const float> m,
                      std::span<const float> v, std::int64_t step);
/// Reads it and checks that it holds `size` moments: InvalidInput naming the group when not.
AdamState read_adam_state(const h5::File& f, const std::string& group, std::size_t size);

struct RngState {
  std::array<std::uint64_t, 4> state{};
  bool has_spare = false;
  double spare = 0;
};
void write_rng_state(h5::File& f, const RngState& s);
RngState read_rng_state(const h5::File& f);

// --- the training log

/// /training/log [rows, columns] with a `columns` attribute naming them (written only when it has
/// rows), and when a checkpoint falls between two log rows /training/unprinted (the iterations
/// since the last row and their loss sums: see models/common/training.h).
void write_training_log(h5::File& f, const std::vector<double>& log,
                        const std::vector<std::string>& columns,
                        const std::vector<double>& unprinted);
struct TrainingLog {
  std::vector<double> rows, unprinted;  ///< empty when the file has none
  std::string columns;                  ///< space-separated; empty when the file has no log
};
TrainingLog read_training_log(const h5::File& f);

}  // namespace df::io
