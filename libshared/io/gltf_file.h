// glTF 2.0 binary (.glb) export of a mesh sequence (through Debian's tinygltf): the first frame
// as the base mesh, every frame as a morph target (its positions and normals less the base's),
// and one animation whose weights switch the targets on in turn — frame k at time k / fps,
// linear between frames — so Blender, three.js and other glTF players play the sequence.
#pragma once

#include <string>
#include <vector>

#include "io/mesh_io.h"

namespace df::io {

struct GltfSequence {
  Faces faces;                  ///< [T, 3]
  std::vector<Vertices> frames;  ///< [F] positions [V, 3], F >= 1
  std::vector<Vertices> normals;  ///< [F] unit vertex normals [V, 3], or empty: none written
  double fps = 30;
  std::string name = "sequence";
};

/// Writes `path` (.glb; the caller makes it atomic). InvalidInput for frames of unequal size.
void write_gltf_sequence(const std::string& path, const GltfSequence& s);

}  // namespace df::io
