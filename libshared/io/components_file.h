// The `components` file kind (schemas/components.json) and its one reader and writer: deformation
// components as normalized ACAP features per level, with their strength (eq. 7 of paper 2), the
// vertex each is centred on, the block and code they come from, whether pruning kept them, and a
// model's attention masks and similarity matrix; and their export as an acap file (one sequence
// per level) for acap2obj, render-mesh and eval-metrics.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "io/acap_file.h"
#include "io/h5.h"
#include "io/mesh_io.h"

namespace df::io {

struct ComponentLevel {
  /// [K, 9V] normalized ACAP features of each component; position components: [K, 3V]
  /// displacements from the mean shape
  h5::RowMatrix<float> features;
  std::vector<double> strength;
  std::vector<int> center;   ///< vertex index (argmax of the block's ‖C_{k,i}‖)
  std::vector<int> block;    ///< the block it comes from (model order)
  std::vector<double> code;  ///< s: the code value decoded (signed)
  std::vector<std::uint8_t> kept;
};

struct Components {
  /// "acap" (normalized ACAP features: every model's and the ACAP-space baselines'), or
  /// "positions" (SPLOCS on vertex positions: displacements from `mean`, one level)
  std::string space = "acap";
  Vertices mean;  ///< positions only: the mean shape [V, 3]
  int per_vertex() const { return space == "positions" ? 3 : 9; }
  Mesh tmpl;
  FeatureNormalization normalization;
  std::string history;
  std::string model;  ///< the model file's name as given
  std::vector<ComponentLevel> levels;
  h5::RowMatrix<float> attention;    ///< level 0's attention masks [K₀, V] (paper 2, eq. 6)
  h5::RowMatrix<double> similarity;  ///< |cosine| between level-0 components' X − X_r [K₀, K₀]
  double eps1 = 1e-6, eps2 = 0.01;
};

void write_components(const std::string& path, const Components& c,
                      const std::vector<std::string>& inputs, bool force);
/// InvalidInput (naming the file and object) when a level's datasets disagree with the template
/// or with each other.
Components read_components(const std::string& path);
/// InvalidInput naming the file when `c` holds position components: `what` needs ACAP ones.
void require_acap_components(const Components& c, const std::string& path, const std::string& what);

/// The components (only the kept ones when `kept_only`) as an acap file: one sequence per level
/// ("level0", ...), frames named "L<level>.<block>.<k>" — for acap2obj, render-mesh --color
/// deformation, eval-metrics.
void write_components_acap(const std::string& path, const Components& c, bool kept_only,
                           const std::vector<std::string>& inputs, bool force);

/// Component k of `level` as write_components_acap names it: "L<level>.<block>.<k within its
/// block>".
std::string component_name(const Components& c, std::size_t level, std::size_t k);

/// Whether an acap file's frames are components as write_components_acap names them (every
/// sequence "level<l>", its frames "L<l>.<block>.<k>"): render-mesh captions them by name.
bool names_components(const std::vector<std::string>& sequence_names,
                      const std::vector<std::string>& frame_names,
                      const std::vector<std::int64_t>& offsets);

}  // namespace df::io
