// Quake II MD2 keyframe models (e.g. Debian's assimp-testmodels: MD2/faerie.md2, sydney.md2):
// one triangle list, many frames of 8-bit-quantized vertex positions. Frame names are the
// animation name followed by a frame number ("stand01", "run3"); consecutive frames with the
// same name stem form one named animation.
#pragma once

#include <string>
#include <vector>

#include "io/mesh_io.h"

namespace df::io {

struct Md2Animation {
  std::string name;
  int first = 0;  ///< first frame index
  int count = 0;
};

struct Md2Model {
  Faces faces;                   ///< counter-clockwise triangles (MD2 stores clockwise)
  std::vector<Vertices> frames;  ///< #V by 3 positions per frame
  std::vector<std::string> frame_names;
  std::vector<Md2Animation> animations;
};

/// Reads an MD2 file; InvalidInput on a bad signature, version or out-of-range offsets.
Md2Model read_md2(const std::string& path);

bool is_md2_file(const std::string& path);

}  // namespace df::io
