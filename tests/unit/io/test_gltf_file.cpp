// The glTF export read back by assimp: every frame's positions equal to the source's within float
// precision, the animation's key times at k / fps, bad input refused.
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <catch2/catch.hpp>
#include <cmath>

#include "helpers.h"
#include "io/gltf_file.h"

using namespace df;
using df::test::TempDir;

namespace {
// `path` read back by assimp (the importer owns the scene).
const aiScene* read_back(Assimp::Importer& importer, const std::string& path) {
  const aiScene* scene = importer.ReadFile(path, 0);
  REQUIRE(scene);
  return scene;
}
}  // namespace

TEST_CASE("glTF export: assimp reads every frame back", "[io]") {
  TempDir dir;
  io::GltfSequence s;
  s.faces.resize(2, 3);
  s.faces << 0, 1, 2, 0, 2, 3;
  for (int k = 0; k < 5; ++k) {
    Vertices v(4, 3);
    const double a = 0.3 * k;
    v << 0, 0, 0, 1, std::sin(a), 0, 1, 1, std::cos(a), 0, 1, 0.1 * k;
    s.frames.push_back(v);
  }
  s.fps = 10;
  const auto path = dir / "s.glb";
  io::write_gltf_sequence(path, s);
  Assimp::Importer importer;
  const aiScene* scene = read_back(importer, path);
  REQUIRE(scene->mNumMeshes == 1);
  const aiMesh* mesh = scene->mMeshes[0];
  REQUIRE(mesh->mNumVertices == 4);
  REQUIRE(mesh->mNumFaces == 2);
  REQUIRE(mesh->mNumAnimMeshes == 5);
  for (unsigned k = 0; k < 5; ++k)
    for (unsigned i = 0; i < 4; ++i) {
      // a target's positions: assimp adds the target's offsets to the base
      const aiVector3D p = mesh->mAnimMeshes[k]->mVertices[i];
      for (int c = 0; c < 3; ++c) CHECK(std::abs(p[c] - s.frames[k](i, c)) < 1e-6);
    }
  for (unsigned i = 0; i < 4; ++i)
    for (int c = 0; c < 3; ++c) CHECK(std::abs(mesh->mVertices[i][c] - s.frames[0](i, c)) < 1e-6);
  REQUIRE(scene->mNumAnimations == 1);
  const aiAnimation* anim = scene->mAnimations[0];
  REQUIRE(anim->mNumMorphMeshChannels == 1);
  const aiMeshMorphAnim* morph = anim->mMorphMeshChannels[0];
  REQUIRE(morph->mNumKeys == 5);
  CHECK(morph->mKeys[3].mTime / (anim->mTicksPerSecond > 0 ? anim->mTicksPerSecond : 1) ==
        Approx(0.3).margin(1e-6));
}

TEST_CASE("glTF export: frames of unequal size are refused", "[io]") {
  TempDir dir;
  io::GltfSequence s;
  s.faces.resize(1, 3);
  s.faces << 0, 1, 2;
  s.frames = {Vertices::Zero(3, 3), Vertices::Zero(4, 3)};
  CHECK_THROWS_WITH(io::write_gltf_sequence(dir / "x.glb", s),
                    Catch::Contains("another vertex count"));
  s.frames.clear();
  CHECK_THROWS_WITH(io::write_gltf_sequence(dir / "x.glb", s), Catch::Contains("no frames"));
}

TEST_CASE("glTF export: a skeleton's joints read back as animated nodes", "[io]") {
  TempDir dir;
  io::GltfSkeleton s;
  s.parents = {-1, 0, 1};
  s.joint_names = {"hip", "knee", "foot"};
  for (int t = 0; t < 4; ++t)
    for (float v : {0.0f, 1.0f + 0.1f * t, 0.0f, 0.0f, 0.5f, 0.2f * t, 0.3f, 0.0f, 0.1f * t})
      s.positions.push_back(v);
  s.fps = 20;
  const auto path = dir / "k.glb";
  io::write_gltf_skeleton(path, s);
  Assimp::Importer importer;
  const aiScene* scene = read_back(importer, path);
  const aiNode* knee = scene->mRootNode->FindNode("knee");
  REQUIRE(knee);
  REQUIRE(knee->mParent->mName == aiString("hip"));
  REQUIRE(scene->mNumAnimations == 1);
  const aiAnimation* anim = scene->mAnimations[0];
  REQUIRE(anim->mNumChannels == 3);
  for (unsigned c = 0; c < 3; ++c) {
    const aiNodeAnim* ch = anim->mChannels[c];
    const int j = ch->mNodeName == aiString("hip") ? 0 : ch->mNodeName == aiString("knee") ? 1 : 2;
    REQUIRE(ch->mNumPositionKeys == 4);
    for (unsigned t = 0; t < 4; ++t)
      for (int k = 0; k < 3; ++k) {  // the offset from the parent
        const float p =
            s.positions[(t * 3 + j) * 3 + k] - (j ? s.positions[(t * 3 + j - 1) * 3 + k] : 0.0f);
        CHECK(std::abs(ch->mPositionKeys[t].mValue[k] - p) < 1e-6);
      }
  }
}
