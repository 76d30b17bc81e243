// The basic mesh types every module shares (issue 69): positions and triangles as Eigen matrices.
// They sit at the bottom, so that geometry and the networks use meshes without the file formats
// (io/mesh_io.h reads and writes them).
#pragma once

#include <Eigen/Core>

namespace df {

/// #V by 3 vertex positions (mesh units), row-major.
using Vertices = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// #F by 3 triangles, 0-based vertex indices.
using Faces = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

struct Mesh {
  Vertices vertices;
  Faces faces;
};

}  // namespace df
