// Deformation components of a trained MSAE (paper 2, §4.2-4.3): decoded from its blocks
// (extract-components' job, apps/msae_components) and pruned by strength (prune-components'); the
// `components` file kind is io/components_file's.
//
// Component k of block b: the decoder applied to the one-hot code s·e_k, with s the largest
// positive or the most negative value of z_k over the training shapes (both signs are decoded and
// the one with the larger strength is kept), as the deformation that code adds to the block's
// zero code, applied to the reference: X = X_r + Dec_b(s·e_k) − Dec_b(0). Second-level blocks
// reconstruct residuals, so this is the one definition that makes every level's components
// shapes; for AE₀ it removes the constant background Dec₀(0) that would otherwise count towards
// every component's strength. Strength (eq. 7): the mean of ‖(X − X_r)_i‖ over the vertices where
// it exceeds ε₁; a component is kept when its strength is at least ε₂.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "geometry/acap_features.h"
#include "io/components_file.h"
#include "io/mesh_io.h"
#include "models/msae/model.h"

namespace df::models {

using io::ComponentLevel;
using io::Components;
using io::read_components;
using io::write_components;
using io::write_components_acap;

/// ‖(X − X_r)_i‖ per vertex of features x [9V]: how much a component deforms each vertex.
std::vector<double> deformation_per_vertex(const float* x, int n_vertices,
                                           const std::array<double, 9>& reference);

/// Eq. 7's parts for a component's per-vertex deformation d: its strength (the mean of d over the
/// `counted` vertices with d > eps1), its support (vertices reaching 10% of the peak) and the same
/// mean over the support only. A decoded component that moves every vertex by a little more than
/// eps1 is counted over the whole mesh, so a local one's strength falls with the mesh's size.
struct StrengthParts {
  double strength = 0, support_strength = 0;
  int counted = 0, support = 0;
};
StrengthParts strength_parts(const std::vector<double>& d, double eps1);

/// Eq. 7 for a component's features x [9V] and the reference's X_r.
double component_strength(const float* x, int n_vertices, const std::array<double, 9>& reference,
                          double eps1);

/// |cosine| between the X − X_r of a level's components [K, K] (paper Fig. 3).
nn::Matrix<double> level0_similarity(const ComponentLevel& level0,
                                     const std::array<double, 9>& ref);

/// Every block's codes of the rows `rows` of `data` [N, 9V] through the first `levels` levels (0:
/// all), 64 shapes at a time: [rows, kz] per block, empty for blocks below those levels.
std::vector<nn::Matrix<float>> block_codes(const MsaeNet<float>& net, const nn::Matrix<float>& data,
                                           const std::vector<std::int64_t>& rows, int levels);
/// Every block's codes of `shapes` [n, 9V] through all levels (in chunks): [n, kz] per block.
std::vector<nn::Matrix<float>> block_codes(const MsaeNet<float>& net,
                                           const nn::Matrix<float>& shapes);

/// Block b's components appended to `out`: each decoded at the training shapes' largest and most
/// negative code (`codes` [n, kz]; ±1 without shapes), the sign of the larger eq. 7 strength kept.
void decode_block(const MsaeNet<float>& net, int b, const nn::Matrix<float>& codes,
                  const std::vector<int>& centres, const std::array<double, 9>& ref, double eps1,
                  ComponentLevel& out);

/// The components of every block; `training_codes` are the training shapes' codes
/// (block_codes), which give the scale of each one-hot code. All components start kept.
Components extract_components(const MsaeModel& m,
                              const std::vector<nn::Matrix<float>>& training_codes);

/// Recomputes strengths with eps1 and keeps those with strength ≥ eps2.
void prune_components(Components& c, double eps1, double eps2);

}  // namespace df::models
