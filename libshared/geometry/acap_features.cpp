#include "geometry/acap_features.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <exception>

#include "core/error.h"
#include "geometry/cotangent_weights.h"
#include "geometry/polar_decomposition.h"

namespace df::geometry {

AcapFeatureExtractor::AcapFeatureExtractor(const Vertices& reference, const Faces& faces,
                                           ConsistencyOptions opt)
    : topo_(mesh_topology(faces, static_cast<int>(reference.rows()))),
      gradients_(std::make_unique<DeformationGradientSolver>(
          reference, faces, topo_, cotangent_weights(reference, faces, topo_))),
      consistency_(topo_, opt) {}

void AcapFeatureExtractor::decompose(const Vertices& frame, FrameDecomposition& out) const {
  std::vector<Eigen::Matrix3d> T;
  gradients_->compute(frame, T);
  std::vector<PolarDecomposition> p(T.size());
  polar_decompose(T, p);
  out.rotation.resize(T.size());
  out.stretch.resize(T.size());
  for (std::size_t i = 0; i < T.size(); ++i) {
    out.rotation[i] = rotation_log(p[i].R);
    out.stretch[i] = p[i].S;
  }
}

ConsistencyReport AcapFeatureExtractor::make_consistent(
    const FrameDecomposition& d, const std::vector<Eigen::Vector3d>* previous,
    std::vector<Eigen::Vector3d>& r) const {
  return consistency_.solve(d.rotation, previous, r);
}

std::vector<Eigen::Vector3d> principal_rotation_vectors(const FrameDecomposition& d) {
  std::vector<Eigen::Vector3d> r(d.rotation.size());
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = d.rotation[i].axis * d.rotation[i].angle;
  return r;
}

void pack_features(const std::vector<Eigen::Vector3d>& r, const std::vector<Eigen::Matrix3d>& S,
                   double* out) {
  for (std::size_t i = 0; i < r.size(); ++i) {
    double* f = out + kFeatureDims * i;
    f[0] = -r[i].z();  // L01
    f[1] = r[i].y();   // L02
    f[2] = -r[i].x();  // L12
    const auto& s = S[i];
    f[3] = s(0, 0);
    f[4] = s(0, 1);
    f[5] = s(0, 2);
    f[6] = s(1, 1);
    f[7] = s(1, 2);
    f[8] = s(2, 2);
  }
}

void unpack_features(const double* f, Eigen::Vector3d& r, Eigen::Matrix3d& S) {
  r = Eigen::Vector3d(-f[2], f[1], -f[0]);
  S << f[3], f[4], f[5], f[4], f[6], f[7], f[5], f[7], f[8];
}

void NormalizationBuilder::add(const double* features, std::size_t rows) {
  for (std::size_t i = 0; i < rows; ++i)
    for (int d = 0; d < kFeatureDims; ++d) {
      double x = features[i * kFeatureDims + d];
      lo_[d] = std::min(lo_[d], x);
      hi_[d] = std::max(hi_[d], x);
    }
}

void NormalizationBuilder::merge(const NormalizationBuilder& o) {
  for (int d = 0; d < kFeatureDims; ++d) {
    lo_[d] = std::min(lo_[d], o.lo_[d]);
    hi_[d] = std::max(hi_[d], o.hi_[d]);
  }
}

Normalization NormalizationBuilder::finish() const {
  Normalization n;
  n.mode = mode_;
  n.min = lo_;
  n.max = hi_;
  if (mode_ == NormalizationMode::group) {
    for (auto [b, e] : {std::pair{0, 3}, std::pair{3, 9}}) {
      double lo = *std::min_element(lo_.begin() + b, lo_.begin() + e);
      double hi = *std::max_element(hi_.begin() + b, hi_.begin() + e);
      for (int d = b; d < e; ++d) n.min[d] = lo, n.max[d] = hi;
    }
  }
  for (int d = 0; d < kFeatureDims; ++d) {
    n.min[d] -= 1e-6;
    n.max[d] += 1e-6;
  }
  return n;
}

std::array<double, kFeatureDims> identity_features(const Normalization* nz) {
  std::array<double, kFeatureDims> id = {0, 0, 0, 1, 0, 0, 1, 0, 1};
  if (nz)
    for (int d = 0; d < kFeatureDims; ++d)
      id[static_cast<std::size_t>(d)] = nz->normalize(d, id[static_cast<std::size_t>(d)]);
  return id;
}

ConsistencyReport FeatureSequence::add(const FrameDecomposition& d, bool start, double* out) {
  ConsistencyReport rep;
  if (consistency_) {
    rep = ex_.make_consistent(d, start ? nullptr : &previous_, r_);
    previous_ = r_;
  } else {
    r_ = principal_rotation_vectors(d);
  }
  pack_features(r_, d.stretch, out);
  return rep;
}

std::vector<double> sequence_features(const AcapFeatureExtractor& ex,
                                      const std::vector<Vertices>& frames,
                                      const std::vector<char>& starts, bool consistency) {
  const std::size_t n = frames.size(), nv = static_cast<std::size_t>(ex.n_vertices());
  std::vector<FrameDecomposition> dec(n);
  std::vector<std::exception_ptr> errors(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t k) {
    try {
      if (static_cast<std::size_t>(frames[k].rows()) != nv)
        throw InvalidInput(
            fmt::format("frame {} has {} vertices, the reference {}", k, frames[k].rows(), nv));
      ex.decompose(frames[k], dec[k]);
    } catch (...) {
      errors[k] = std::current_exception();
    }
  });
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
  std::vector<double> out(n * nv * kFeatureDims);
  FeatureSequence seq(ex, consistency);
  for (std::size_t k = 0; k < n; ++k)
    seq.add(dec[k], k == 0 || (k < starts.size() && starts[k]), out.data() + k * nv * kFeatureDims);
  return out;
}

}  // namespace df::geometry
