#include "models/baselines/baselines.h"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/error.h"

namespace df::models {

using Eigen::Index;
using Mat = nn::Matrix<double>;

Pca fit_pca(const Mat& x, int k) {
  Pca p;
  p.mean = x.colwise().mean();
  const Mat y = x.rowwise() - p.mean.row(0);
  // Few shapes, many features: the eigenvectors of the n × n Gram matrix give the directions.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(y * y.transpose());
  const Eigen::VectorXd values = eig.eigenvalues();  // ascending
  const double top = values.size() ? values.maxCoeff() : 0.0;
  std::vector<Mat> rows;
  for (Index j = values.size() - 1; j >= 0 && static_cast<int>(rows.size()) < k; --j) {
    if (!(values[j] > 1e-12 * top)) break;
    rows.push_back((eig.eigenvectors().col(j).transpose() * y) / std::sqrt(values[j]));
  }
  p.directions.resize(static_cast<Index>(rows.size()), x.cols());
  for (std::size_t r = 0; r < rows.size(); ++r) p.directions.row(static_cast<Index>(r)) = rows[r];
  return p;
}

Mat coefficients_on(const Mat& y, const Mat& mean, const Mat& basis) {
  const Mat centred = y.rowwise() - mean.row(0);
  Eigen::MatrixXd G = basis * basis.transpose();
  G.diagonal().array() += 1e-10 * std::max(G.trace(), 1e-300);
  return Eigen::LDLT<Eigen::MatrixXd>(G).solve(basis * centred.transpose()).transpose();
}

Mat project_onto(const Mat& y, const Mat& mean, const Mat& basis) {
  if (basis.rows() == 0) return mean.replicate(y.rows(), 1);
  return (coefficients_on(y, mean, basis) * basis).rowwise() + mean.row(0);
}

}  // namespace df::models
