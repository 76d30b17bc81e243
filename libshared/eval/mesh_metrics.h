// Error measures between a predicted and a ground-truth mesh (same connectivity), SPEC §9:
// per-vertex position error (paper 1 Tables 1-2), E_rms (paper 2 Table 2), STED (Vasa & Skala
// 2011), relative squared error of ACAP features (paper 2 eq. 8), feature change between frames
// (paper 1 Fig. 2). Pure functions on one frame or pair of frames; eval_metrics.h aggregates.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "geometry/mesh_topology.h"
#include "io/mesh_io.h"

namespace df::eval {

/// Moves each connected component of `pred` so that its centroid matches `truth`'s (the
/// reconstruction fixes positions only up to one translation per component).
Vertices align_translation(const Vertices& pred, const Vertices& truth,
                           const std::vector<int>& component, int n_components);

/// Moves each connected component of `pred` by the rotation and translation that best fit it to
/// `truth`'s (Kabsch: least squares over the component's vertices, no reflection): the paper's
/// "align all the models" before E_rms (MSAE paper §5.1). A reconstruction from ACAP features is
/// fixed up to one translation per component only, but an error in the features can turn a whole
/// part; this alignment forgives that turn, translation-only does not.
Vertices align_rigid(const Vertices& pred, const Vertices& truth, const std::vector<int>& component,
                     int n_components);

/// A mesh's connected parts: the error measures align each on its own (a reconstruction from ACAP
/// features is fixed up to one translation per part).
struct MeshParts {
  std::vector<int> of_vertex;  ///< the part of each vertex
  int count = 1;
};

/// The connected parts of a mesh with these faces (no faces: one part of all `vertices`).
MeshParts mesh_parts(const Faces& faces, Eigen::Index vertices);
MeshParts mesh_parts(const geometry::MeshTopology& topo);

enum class Alignment { translation, rigid };

/// `pred` moved onto `truth` part by part: align_translation or align_rigid.
Vertices align_parts(const Vertices& pred, const Vertices& truth, const MeshParts& parts,
                     Alignment how = Alignment::translation);

/// One frame's share of E_rms, as every E_rms here is measured: unit_ball_squared_error of `pred`
/// aligned to `truth` part by part (translation). E_rms over frames: erms_from_sum of their sum.
double erms_share(const Vertices& pred, const Vertices& truth, const MeshParts& parts);

/// Mean over vertices of ‖pred_i − truth_i‖.
double mean_vertex_error(const Vertices& pred, const Vertices& truth);

/// Σ‖A − A′‖² over the vertices after translating the truth's centroid to the origin and
/// scaling it into the unit ball (the same transform applied to pred). E_rms over N frames is
/// 1000 · sqrt(Σ_frames / (3 N V)).
double unit_ball_squared_error(const Vertices& pred, const Vertices& truth);

/// E_rms × 1000 from unit_ball_squared_error summed over `frames` frames of `vertices` vertices.
double erms_from_sum(double unit_ball_sum, double frames, double vertices);

/// Edges within k rings of each vertex (k = 1: the incident edges), for STED's neighbourhoods.
std::vector<std::vector<int>> edge_neighbourhoods(const geometry::MeshTopology& topo, int rings);

/// STED's spatial part for one frame: per edge ed = |l′ − l| / l; per vertex the standard
/// deviation of ed over its neighbourhood weighted by l; the mean over vertices.
double sted_spatial(const Vertices& pred, const Vertices& truth, const geometry::MeshTopology& topo,
                    const std::vector<std::vector<int>>& neighbourhoods);

/// STED's temporal part for one pair of consecutive frames (t, t+1): per vertex the relative
/// speed s = ‖p_i(t+1) − p_i(t)‖ / (dt · mean incident edge length at t) of each mesh, and the
/// mean over vertices of |s_pred − s_truth|.
double sted_temporal(const Vertices& pred0, const Vertices& pred1, const Vertices& truth0,
                     const Vertices& truth1, const geometry::MeshTopology& topo, double dt);

/// ‖X − X̂‖²_F / ‖X‖²_F (features of one frame).
double relative_squared_error(const Eigen::Ref<const Eigen::VectorXd>& x,
                              const Eigen::Ref<const Eigen::VectorXd>& xhat);

/// ‖X_t − X_{t+1}‖ / ‖X_t‖.
double feature_change(const Eigen::Ref<const Eigen::VectorXd>& xt,
                      const Eigen::Ref<const Eigen::VectorXd>& xt1);

}  // namespace df::eval
