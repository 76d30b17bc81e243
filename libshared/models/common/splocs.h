// Sparse localized deformation components (Neumann, Richardson, Rhodin, Theobalt, Magnor,
// "Sparse Localized Deformation Components", SIGGRAPH Asia 2013, following the authors' reference
// code) on rows of any per-vertex group size: a baseline of MSAE's tables (models/baselines, on
// positions and on ACAP features) and the local decomposition MSAE's level 0 can start from
// (models/msae, --init local).
#pragma once

#include <Eigen/Core>
#include <functional>

#include "nn/tape.h"

namespace df::models {

struct SplocsOptions {
  int components = 50;
  int iterations = 10;  ///< outer iterations (the reference code's default)
  int admm_iterations = 10;
  double lambda = 2.0, rho = 10.0;
  double d_min = 0.1, d_max = 0.7;  ///< support map ramps over these normalized geodesic distances
};
/// Components [K, gV] of rows x [n, gV], `group` numbers per vertex (3: positions; 9: ACAP
/// features), mean removed and scaled by their standard deviation (`mean` [1, gV] and `scale`
/// come back); `distance(i)` gives vertex i's normalized geodesic row.
struct Splocs {
  nn::Matrix<double> mean, components;
  double scale = 1;
};
Splocs fit_splocs(const nn::Matrix<double>& x, const SplocsOptions& opt,
                  const std::function<Eigen::VectorXf(int)>& distance, int group = 3);

/// The group (vertex) of largest norm of a row of g numbers per vertex.
Eigen::Index strongest_vertex(const Eigen::RowVectorXd& c, Eigen::Index g);

}  // namespace df::models
