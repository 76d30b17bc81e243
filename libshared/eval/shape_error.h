// E_rms (paper 2, Table 2) of shapes given as normalized ACAP features against the data file's
// own shapes, measured as eval-metrics measures them (positions from the exact solver, one
// translation per connected part removed, the truth scaled into the unit ball): the column
// train-msae logs for its validation shapes, so that iteration counts and options are chosen by
// the measure the tables report.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "eval/mesh_metrics.h"
#include "geometry/acap_features.h"
#include "geometry/reconstruction.h"
#include "io/mesh_io.h"

namespace df::eval {

class ShapeErms {
 public:
  /// @param data    an acap file; its frames `frames` are the truth (stored positions, or
  ///                reconstructed from its features once, here)
  /// @param nz      the normalization of the features that operator() receives
  ShapeErms(const std::string& data, const std::vector<std::int64_t>& frames,
            const geometry::Normalization& nz);
  ~ShapeErms();
  /// E_rms × 1000 of `normalized` (one row of 9V normalized features per frame of `frames`, in
  /// that order). Frames in parallel; the sum is taken in frame order (thread-count independent).
  double operator()(const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>&
                        normalized) const;

 private:
  geometry::Normalization nz_;
  std::unique_ptr<geometry::Reconstructor> solver_;
  std::vector<Vertices> truth_;
  MeshParts parts_;
};

}  // namespace df::eval
