// The parts every mesh model file shares (bdlstm-model now, msae-model next): the template the
// model was trained on, the normalization of its training features, and the training log with
// its column names. Each model writes its own /config and extras around these.
#pragma once

#include <string>
#include <vector>

#include "geometry/acap_features.h"
#include "io/h5.h"
#include "io/mesh_io.h"

namespace df::models {

/// Writes /template/{vertices,faces}, /normalization and, when `log` has rows, /training/log
/// [rows, columns] with a `columns` attribute naming them; when a checkpoint falls between two
/// log rows, /training/unprinted (the iterations since the last row and their loss sums: see
/// run_training_loop).
void write_mesh_model_common(h5::File& f, const Mesh& tmpl, const geometry::Normalization& nz,
                             const std::vector<double>& log,
                             const std::vector<std::string>& columns,
                             const std::vector<double>& unprinted);

/// Reads what write_mesh_model_common wrote (an absent log or unprinted part reads as empty).
void read_mesh_model_common(const h5::File& f, Mesh& tmpl, geometry::Normalization& nz,
                            std::vector<double>& log, std::vector<double>& unprinted);

}  // namespace df::models
