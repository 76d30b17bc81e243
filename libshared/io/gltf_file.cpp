#include "io/gltf_file.h"

#include <tiny_gltf.h>

#include <cstring>
#include <map>

#include "core/error.h"

namespace df::io {
namespace {

// Appends data to the one buffer as a view and an accessor of `components` numbers per element
// (with its min / max when `bounds`: glTF asks them of positions and times); returns the
// accessor's index.
template <class T>
int add_accessor(tinygltf::Model& m, const std::vector<T>& data, int component_type, int type,
                 int components, bool bounds, int target) {
  auto& buf = m.buffers[0].data;
  const std::size_t offset = buf.size(), bytes = data.size() * sizeof(T);
  buf.resize(offset + bytes);
  std::memcpy(buf.data() + offset, data.data(), bytes);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = offset;
  view.byteLength = bytes;
  if (target) view.target = target;
  m.bufferViews.push_back(view);
  tinygltf::Accessor a;
  a.bufferView = static_cast<int>(m.bufferViews.size()) - 1;
  a.componentType = component_type;
  a.count = data.size() / static_cast<std::size_t>(components);
  a.type = type;
  if (bounds) {
    a.minValues.assign(static_cast<std::size_t>(components), 1e300);
    a.maxValues.assign(static_cast<std::size_t>(components), -1e300);
    for (std::size_t i = 0; i < data.size(); ++i) {
      auto& lo = a.minValues[i % static_cast<std::size_t>(components)];
      auto& hi = a.maxValues[i % static_cast<std::size_t>(components)];
      lo = std::min(lo, static_cast<double>(data[i]));
      hi = std::max(hi, static_cast<double>(data[i]));
    }
  }
  m.accessors.push_back(a);
  return static_cast<int>(m.accessors.size()) - 1;
}

int add_floats(tinygltf::Model& m, const std::vector<float>& data, int type, int components,
               bool bounds, int target = TINYGLTF_TARGET_ARRAY_BUFFER) {
  return add_accessor(m, data, TINYGLTF_COMPONENT_TYPE_FLOAT, type, components, bounds, target);
}

// The animation's key times, frame k at k / fps, as an accessor (its samplers' input).
int add_key_times(tinygltf::Model& m, std::size_t frames, double fps) {
  std::vector<float> times(frames);
  for (std::size_t k = 0; k < frames; ++k)
    times[k] = static_cast<float>(static_cast<double>(k) / fps);
  return add_floats(m, times, TINYGLTF_TYPE_SCALAR, 1, true, 0);
}

// A linear sampler from the key times `input` to the values `output`, driving `path` of `node`.
void add_channel(tinygltf::Animation& anim, int input, int output, int node,
                 const std::string& path) {
  tinygltf::AnimationSampler sampler;
  sampler.input = input;
  sampler.output = output;
  sampler.interpolation = "LINEAR";
  anim.samplers.push_back(sampler);
  tinygltf::AnimationChannel channel;
  channel.sampler = static_cast<int>(anim.samplers.size()) - 1;
  channel.target_node = node;
  channel.target_path = path;
  anim.channels.push_back(channel);
}

tinygltf::Model new_model() {
  tinygltf::Model m;
  m.asset.version = "2.0";
  m.asset.generator = "deformflow";
  m.buffers.emplace_back();
  return m;
}

void save(tinygltf::Model& m, const std::string& path) {
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToFile(&m, path, true, true, false, true))
    throw IOError("cannot write the glTF file", path);
}

std::vector<float> flat(const Vertices& v, const Vertices* minus = nullptr) {
  std::vector<float> out(static_cast<std::size_t>(v.size()));
  for (Eigen::Index i = 0; i < v.size(); ++i)
    out[static_cast<std::size_t>(i)] =
        static_cast<float>(v.data()[i] - (minus ? minus->data()[i] : 0.0));
  return out;
}

}  // namespace

void write_gltf_sequence(const std::string& path, const GltfSequence& s) {
  if (s.frames.empty()) throw InvalidInput("no frames to export", path);
  const Vertices& base = s.frames.front();
  const bool normals = !s.normals.empty();
  if (normals && s.normals.size() != s.frames.size())
    throw InvalidInput("normals are not one per frame", path);
  for (std::size_t k = 0; k < s.frames.size(); ++k)
    if (s.frames[k].rows() != base.rows() || (normals && s.normals[k].rows() != base.rows()))
      throw InvalidInput("frame " + std::to_string(k) + " has another vertex count", path);
  tinygltf::Model m = new_model();
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.attributes["POSITION"] = add_floats(m, flat(base), TINYGLTF_TYPE_VEC3, 3, true);
  if (normals)
    prim.attributes["NORMAL"] =
        add_floats(m, flat(s.normals.front()), TINYGLTF_TYPE_VEC3, 3, false);
  std::vector<std::uint32_t> indices(static_cast<std::size_t>(s.faces.size()));
  for (Eigen::Index i = 0; i < s.faces.size(); ++i)
    indices[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(s.faces.data()[i]);
  prim.indices = add_accessor(m, indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                              TINYGLTF_TYPE_SCALAR, 1, false, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  const std::size_t F = s.frames.size();
  for (std::size_t k = 0; k < F; ++k) {
    std::map<std::string, int> target{
        {"POSITION", add_floats(m, flat(s.frames[k], &base), TINYGLTF_TYPE_VEC3, 3, true)}};
    if (normals)
      target["NORMAL"] =
          add_floats(m, flat(s.normals[k], &s.normals.front()), TINYGLTF_TYPE_VEC3, 3, false);
    prim.targets.push_back(target);
  }
  tinygltf::Mesh mesh;
  mesh.name = s.name;
  mesh.primitives.push_back(prim);
  mesh.weights.assign(F, 0.0);
  mesh.weights[0] = 1.0;
  m.meshes.push_back(mesh);
  tinygltf::Node node;
  node.name = s.name;
  node.mesh = 0;
  m.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  m.scenes.push_back(scene);
  m.defaultScene = 0;
  // The animation: at time k / fps the weights are the k-th unit vector.
  std::vector<float> weights(F * F, 0.0f);
  for (std::size_t k = 0; k < F; ++k) weights[k * F + k] = 1;
  tinygltf::Animation anim;
  anim.name = s.name;
  const int times = add_key_times(m, F, s.fps);
  add_channel(anim, times, add_floats(m, weights, TINYGLTF_TYPE_SCALAR, 1, false, 0), 0, "weights");
  m.animations.push_back(anim);
  save(m, path);
}

void write_gltf_skeleton(const std::string& path, const GltfSkeleton& s) {
  const std::size_t J = s.parents.size();
  if (J == 0 || s.joint_names.size() != J || s.positions.size() % (3 * J) != 0 ||
      s.positions.empty())
    throw InvalidInput("the skeleton's joints, names and positions disagree", path);
  const std::size_t T = s.positions.size() / (3 * J);
  for (std::size_t j = 0; j < J; ++j)
    if (s.parents[j] >= static_cast<std::int32_t>(j) && s.parents[j] >= 0)
      throw InvalidInput("joint " + std::to_string(j) + "'s parent does not come before it", path);
  tinygltf::Model m = new_model();
  // translation of joint j at frame t: its position less its parent's (a root: its position)
  const auto offset = [&](std::size_t t, std::size_t j, int c) {
    const float p = s.positions[(t * J + j) * 3 + static_cast<std::size_t>(c)];
    return s.parents[j] < 0 ? p
                            : p - s.positions[(t * J + static_cast<std::size_t>(s.parents[j])) * 3 +
                                              static_cast<std::size_t>(c)];
  };
  tinygltf::Scene scene;
  for (std::size_t j = 0; j < J; ++j) {
    tinygltf::Node node;
    node.name = s.joint_names[j];
    node.translation = {offset(0, j, 0), offset(0, j, 1), offset(0, j, 2)};
    m.nodes.push_back(node);
  }
  for (std::size_t j = 0; j < J; ++j) {
    if (s.parents[j] < 0)
      scene.nodes.push_back(static_cast<int>(j));
    else
      m.nodes[static_cast<std::size_t>(s.parents[j])].children.push_back(static_cast<int>(j));
  }
  m.scenes.push_back(scene);
  m.defaultScene = 0;
  const int times = add_key_times(m, T, s.fps);
  tinygltf::Animation anim;
  anim.name = s.name;
  for (std::size_t j = 0; j < J; ++j) {
    std::vector<float> values(3 * T);
    for (std::size_t t = 0; t < T; ++t)
      for (int c = 0; c < 3; ++c) values[3 * t + static_cast<std::size_t>(c)] = offset(t, j, c);
    add_channel(anim, times, add_floats(m, values, TINYGLTF_TYPE_VEC3, 3, false, 0),
                static_cast<int>(j), "translation");
  }
  m.animations.push_back(anim);
  save(m, path);
}

}  // namespace df::io
