// What a trained MSAE learned, per component and per level (issue 45's diagnosis): where each
// component sits and how local it is, how strong, how much of the held-out shapes' reconstruction
// it carries, and how many independent directions each level's decoder spans against PCA's.
// extract-components --report prints it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "models/msae/components.h"
#include "models/msae/model.h"

namespace df::models {

struct ComponentDiagnosis {
  int block = 0, k = 0, centre = 0;
  double weight_norm = 0;  ///< ‖C_k‖
  /// Share of ‖C_k‖² on vertices within Ω's radius d of the centre (1 = as local as Ω asks);
  /// −1 when the model file has no distances from that centre
  double inside = -1;
  StrengthParts
      eq7;  ///< eq. 7 of the decoded component at its extreme training code, and its parts
  double code_min = 0, code_max = 0;  ///< over the training shapes
  double share = 0;  ///< mean over the held-out shapes of its part of its block's deformation
};

struct LevelDiagnosis {
  int level = 0;
  std::vector<ComponentDiagnosis> components;
  int distinct_centres = 0;
  /// Singular values of the level's decoded deformation directions (X_k − X_r), largest first,
  /// relative to the largest; the effective rank counts those above 1%.
  std::vector<double> singular_values;
  int effective_rank = 0;
};

/// What the second level can do with what it is fed (models of two or more levels): the training
/// shapes' residual after level 0, R, is split among AE₀'s children by the attention masks (each
/// child k reconstructs diag(AM_k)·R; without attention one child gets R whole). Energies are
/// shares of ‖R‖² in normalized features.
struct SecondLevelDiagnosis {
  int children = 0;         ///< AE₀'s children (0: not measured)
  int components = 0;       ///< Σ K_z over the children
  double fed = 0;           ///< Σ_k ‖AM_k ⊙ R‖² / ‖R‖²
  double left_trained = 0;  ///< ‖X − X̂ (levels 0-1)‖² / ‖R‖²
  double left_linear = 0;   ///< best linear children: rank K_z of each masked input, outputs summed
  double left_one = 0;      ///< best rank-`components` reconstruction of R (one linear autoencoder)
  int child_kz = 0;         ///< the largest child's K_z
  double left_one_child =
      0;  ///< best rank-`child_kz` reconstruction of R: what spread masks tend to
  /// The held-out shapes through the encoders, as shares of their residual's energy ‖R‖² after
  /// level 0: each child k leaves e_k = diag(AM_k)·R − X̂_k of its own input, and the shapes are
  /// left with Σ_k e_k. `heldout_own` = Σ_k ‖e_k‖² (what the children's own losses measure),
  /// `heldout_whole` = ‖Σ_k e_k‖²; the difference is the cross terms 2 Σ_{j<k} ⟨e_j, e_k⟩, which
  /// no block's loss sees. −1: not measured (no held-out shapes).
  double heldout_own = -1, heldout_whole = -1;
  double heldout_residual =
      0;  ///< ‖R‖² per held-out shape (normalized features): the shares' scale
};

struct MsaeDiagnosis {
  std::vector<LevelDiagnosis> levels;
  int n_training = 0, n_heldout = 0;
  int n_vertices = 0;
  double eps1 = 0, eps2 = 0;    ///< eq. 7's noise floor and the pruning threshold of the components
  int pca_rank = 0;             ///< rank of the centred training shapes: what PCA can span
  SecondLevelDiagnosis second;  ///< children == 0: one level, or level 0 leaves no residual
};

/// The best linear children's reconstruction of r [n, 9V]: Σ_k P_k(diag(mask_k)·r), P_k the
/// projection onto the top `ranks[k]` left singular vectors of child k's input (the optimum of a
/// linear autoencoder of ranks[k] components on it). masks [K, V]; an empty masks matrix means
/// one child fed r whole. With masks spread over the same vertices, children of rank K_z learn
/// the same top directions and their sum spans little more than one of them.
nn::Matrix<double> best_linear_children(const nn::Matrix<double>& r,
                                        const nn::Matrix<double>& masks,
                                        const std::vector<int>& ranks);

/// The second level's errors on shapes [n, 9V] through the encoders (models of two or more
/// levels; zeros otherwise): R = X − X̂₀ the residual after level 0, child k of AE₀ leaves
/// e_k = diag(AM_k)·R − X̂_k of its own input (R whole without attention).
struct ChildrenErrors {
  double residual = 0;  ///< ‖R‖²
  double own = 0;       ///< Σ_k ‖e_k‖²: what the children's own losses see
  double whole = 0;     ///< ‖Σ_k e_k‖²: what the shapes are left with through levels 0-1
};
ChildrenErrors children_errors(const MsaeNet<float>& net, const nn::Matrix<float>& shapes);

/// Signs that level 0's components have collapsed (issue 65's diagnosis of the Horse set: ten
/// components on three distinct centres, seven decoded over most of the mesh, two carrying the
/// mean deformation with a near-constant code), measured on AE₀ (block 0) from the training
/// shapes: train-msae warns with them at its loss lines and records them in the model file.
struct CollapseSigns {
  int components = 0;        ///< AE₀'s K_z
  int distinct_centres = 0;  ///< distinct peaks c_k = argmax_i ‖C_{k,i}‖
  /// Components whose decoded deformation (at the training shapes' extreme code) reaches 10% of
  /// its peak on more than 80% of the vertices
  int wide = 0;
  /// Components whose code over the training shapes varies by less than a tenth of its size
  /// (the size at least a tenth of the block's largest): a constant offset, not a deformation
  int constant = 0;
  /// Fewer distinct centres than half the components, more than half of them wide, or any
  /// constant code.
  bool collapsed() const;
  /// What collapsed and the options that address it (those the model does not already use),
  /// one line without the "warning:" prefix; "" when nothing collapsed.
  std::string describe(const MsaeConfig& config) const;
};
/// @param data      every shape [N, 9V] (normalized features)
/// @param training  the rows of `data` trained on
CollapseSigns collapse_signs(const MsaeModel& m, const nn::Matrix<float>& data,
                             const std::vector<std::int64_t>& training);

/// @param comps           the model's components (extract_components of training_codes)
/// @param training        the training shapes [n, 9V] (normalized): PCA's rank
/// @param training_codes  every block's codes of them (block_codes): the code ranges
/// @param heldout         shapes not trained on (validation or test part): each component's share
MsaeDiagnosis diagnose_msae(const MsaeModel& m, const Components& comps,
                            const nn::Matrix<float>& training,
                            const std::vector<nn::Matrix<float>>& training_codes,
                            const nn::Matrix<float>& heldout);

/// The diagnosis as a text table (one row per component, a summary per level).
std::string format_diagnosis(const MsaeDiagnosis& d, const std::string& heldout_part);

}  // namespace df::models
