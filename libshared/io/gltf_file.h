// glTF 2.0 binary (.glb) export of a mesh sequence (through Debian's tinygltf): the first frame
// as the base mesh, every frame as a morph target (its positions and normals less the base's),
// and one animation whose weights switch the targets on in turn — frame k at time k / fps,
// linear between frames — so Blender, three.js and other glTF players play the sequence.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "io/mesh_io.h"

namespace df::io {

struct GltfSequence {
  Faces faces;                    ///< [T, 3]
  std::vector<Vertices> frames;   ///< [F] positions [V, 3], F >= 1
  std::vector<Vertices> normals;  ///< [F] unit vertex normals [V, 3], or empty: none written
  double fps = 30;
  std::string name = "sequence";
};

/// Writes `path` (.glb; the caller makes it atomic). InvalidInput for frames of unequal size.
void write_gltf_sequence(const std::string& path, const GltfSequence& s);

/// A skeleton sequence: one node per joint in the joints' hierarchy (a child's translation is
/// its offset from its parent, no rotations), each node's translation animated over the frames.
struct GltfSkeleton {
  std::vector<std::int32_t> parents;     ///< [J], −1 for a root
  std::vector<std::string> joint_names;  ///< [J]
  std::vector<float> positions;          ///< [T, J, 3] joint positions
  double fps = 30;
  std::string name = "skeleton";
};
void write_gltf_skeleton(const std::string& path, const GltfSkeleton& s);

}  // namespace df::io
