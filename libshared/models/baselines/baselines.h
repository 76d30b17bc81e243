// Baselines for MSAE's tables (paper 2, Table 2), fitted on the training shapes of an MSAE model's
// split and evaluated on the same held-out shapes, with the same number of components:
//   pca     principal components of the normalized ACAP features (the mean plus the top K
//           directions; at most #training − 1 exist);
//   splocs  sparse localized deformation components on vertex positions (Neumann, Richardson,
//           Rhodin, Theobalt, Magnor, "Sparse Localized Deformation Components", SIGGRAPH Asia
//           2013, following the authors' reference code): positions minus their mean, divided by
//           their standard deviation; greedy initialisation at the vertex of largest residual;
//           alternating weights (projected to [0, 1]) and components (ADMM with the group-ℓ1/ℓ2
//           proximal step, support maps from normalized geodesic distances between d_min and
//           d_max);
//   splocs-acap  the same algorithm on the normalized ACAP features, 9 numbers per vertex: local
//           linear components in MSAE's own space (a diagnostic baseline, issue 45).
// A held-out shape is reconstructed by least squares on the components (its mean removed).
#pragma once

#include "nn/tape.h"

namespace df::models {

/// Principal components: `mean` [1, D] and the top `k` orthonormal directions as rows [k, D].
struct Pca {
  nn::Matrix<double> mean, directions;
};
Pca fit_pca(const nn::Matrix<double>& x, int k);

/// Least-squares coefficients [m, k] of rows y [m, D] (mean removed) on `basis` [k, D].
nn::Matrix<double> coefficients_on(const nn::Matrix<double>& y, const nn::Matrix<double>& mean,
                                   const nn::Matrix<double>& basis);
/// The reconstruction mean + coefficients · basis of rows y [m, D].
nn::Matrix<double> project_onto(const nn::Matrix<double>& y, const nn::Matrix<double>& mean,
                                const nn::Matrix<double>& basis);

}  // namespace df::models
