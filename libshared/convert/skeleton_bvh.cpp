// BVH through assimp: its BVH loader builds the joint hierarchy as nodes and one animation whose
// channels key each joint's rotation (and the root's position) per frame; the joint positions
// are the nodes' global translations, frame by frame.
#include <assimp/scene.h>
#include <fmt/format.h>

#include <assimp/Importer.hpp>
#include <filesystem>
#include <map>

#include "convert/skeleton_import.h"
#include "core/error.h"

namespace df::convert {
namespace {

// Every node below the scene root, depth first, with its parent's index (-1 for a root).
void collect(const aiNode* node, int parent, std::vector<const aiNode*>& nodes,
             std::vector<std::int32_t>& parents) {
  const int index = static_cast<int>(nodes.size());
  nodes.push_back(node);
  parents.push_back(parent);
  for (unsigned k = 0; k < node->mNumChildren; ++k)
    collect(node->mChildren[k], index, nodes, parents);
}

aiMatrix4x4 local_transform(const aiNode* node, const aiNodeAnim* channel, unsigned frame) {
  if (!channel) return node->mTransformation;
  aiVector3D scaling, position;
  aiQuaternion rotation;
  node->mTransformation.Decompose(scaling, rotation, position);
  if (channel->mNumPositionKeys)
    position = channel->mPositionKeys[std::min(frame, channel->mNumPositionKeys - 1)].mValue;
  if (channel->mNumRotationKeys)
    rotation = channel->mRotationKeys[std::min(frame, channel->mNumRotationKeys - 1)].mValue;
  return aiMatrix4x4(scaling, rotation, position);
}

RawSkeletonSequence read_one(const std::string& path, RawSkeletonCollection& c, bool first) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, 0);
  if (!scene || !scene->mRootNode)
    throw InvalidInput(fmt::format("not a readable BVH file: {}", importer.GetErrorString()), path);
  if (scene->mNumAnimations == 0) throw InvalidInput("BVH file without motion", path);
  const aiAnimation* anim = scene->mAnimations[0];
  std::vector<const aiNode*> nodes;
  std::vector<std::int32_t> parents;
  collect(scene->mRootNode, -1, nodes, parents);
  std::vector<std::string> names;
  for (const auto* n : nodes) names.emplace_back(n->mName.C_Str());
  if (first) {
    c.joint_names = names;
    c.parents = parents;
  } else if (names != c.joint_names || parents != c.parents) {
    throw InvalidInput(
        fmt::format("its joint hierarchy ({} joints) differs from the first file's ({})",
                    names.size(), c.joint_names.size()),
        path);
  }
  std::map<std::string, const aiNodeAnim*> channels;
  unsigned frames = 0;
  for (unsigned k = 0; k < anim->mNumChannels; ++k) {
    const aiNodeAnim* ch = anim->mChannels[k];
    channels[ch->mNodeName.C_Str()] = ch;
    frames = std::max({frames, ch->mNumPositionKeys, ch->mNumRotationKeys});
  }
  if (frames < 2) throw InvalidInput(fmt::format("{} frame(s) of motion", frames), path);
  const double ticks = anim->mTicksPerSecond > 0 ? anim->mTicksPerSecond : 30.0;
  if (first) c.frame_rate = ticks;
  RawSkeletonSequence s;
  s.name = std::filesystem::path(path).stem().string();
  s.poses.reserve(static_cast<std::size_t>(frames) * nodes.size() * 3);
  std::vector<aiMatrix4x4> global(nodes.size());
  for (unsigned f = 0; f < frames; ++f) {
    for (std::size_t j = 0; j < nodes.size(); ++j) {
      const auto it = channels.find(nodes[j]->mName.C_Str());
      const aiMatrix4x4 local =
          local_transform(nodes[j], it == channels.end() ? nullptr : it->second, f);
      global[j] = parents[j] < 0 ? local : global[static_cast<std::size_t>(parents[j])] * local;
      s.poses.push_back(global[j].a4);
      s.poses.push_back(global[j].b4);
      s.poses.push_back(global[j].c4);
    }
    s.times.push_back(f / ticks);
  }
  return s;
}

}  // namespace

RawSkeletonCollection read_bvh(const std::vector<std::string>& files, const std::string& label) {
  RawSkeletonCollection c;
  for (std::size_t k = 0; k < files.size(); ++k) {
    RawSkeletonSequence s = read_one(files[k], c, k == 0);
    s.label = label.empty() ? s.name : label;
    c.sequences.push_back(std::move(s));
  }
  return c;
}

}  // namespace df::convert
