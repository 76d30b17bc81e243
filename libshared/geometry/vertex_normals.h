// Unit vertex normals as OpenMesh's update_normals computes them: the normalized sum of the
// unit normals of the faces around the vertex (zero for a vertex in no proper face).
#pragma once

#include "core/mesh.h"

namespace df::geometry {

/// @param V  #V by 3 positions; @param F  #F by 3 triangles; @return #V by 3 unit normals
Vertices vertex_normals(const Vertices& V, const Faces& F);

}  // namespace df::geometry
