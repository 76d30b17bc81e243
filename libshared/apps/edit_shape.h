// edit-shape's job: a shape edited by dragging handle vertices, in the span of a components file's
// deformation components (geometry/subspace_edit: data-driven deformation, the MSAE paper's §5
// application), coarse then fine through --levels and --from.
#pragma once

#include <string>
#include <vector>

#include "core/common_options.h"
#include "geometry/subspace_edit.h"

namespace df::apps {

struct EditShapeOptions {
  std::string components, handles, from, output;
  std::vector<int> fixed;  ///< vertices held where they are in the shape edited from
  int from_frame = 0;
  /// --sample N handles by furthest-point sampling on the template, their targets in frame
  /// --to-frame of --to (the paper's Fig. 6 protocol: a shape rebuilt from N control points)
  std::string to;
  int to_frame = 0, sample = 0;
  std::vector<int> levels;  ///< empty: every level
  bool include_pruned = false;
  bool relative = false;  ///< the handle file's targets are displacements from the start shape
  bool release_handles = false;  ///< do not hold the handles of --from's own edit
  geometry::SubspaceEditOptions solver;
};

/// A handle file's lines `vertex x y z` (a target) or `vertex` (held where it is); `#` starts a
/// comment. InvalidInput naming the line for a vertex out of range, a target that is not three
/// finite numbers, or a vertex given twice.
struct Handles {
  std::vector<int> vertices;
  std::vector<Eigen::RowVector3d> targets;  ///< NaN rows: held where they are
};
Handles read_handles(const std::string& path, int n_vertices);

/// n vertices spread over the template: vertex 0, then each time the vertex furthest (in
/// space) from those chosen; ties to the lowest index.
std::vector<int> furthest_point_sample(const Vertices& v, int n);

void edit_shape(const EditShapeOptions& opt, const CommonOptions& common);

}  // namespace df::apps
