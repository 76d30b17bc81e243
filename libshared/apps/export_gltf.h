// export-gltf's job: a mesh sequence (an acap file with positions or features, or mesh files) as
// one animated glTF binary (io/gltf_file: morph targets and their animation).
#pragma once

#include <string>

#include "core/common_options.h"

namespace df::apps {

struct ExportGltfOptions {
  std::string input, output, sequence;
  double fps = 30;
  int every = 1;
};

void export_gltf(const ExportGltfOptions& opt, const CommonOptions& common);

}  // namespace df::apps
