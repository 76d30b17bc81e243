#include "render/stick_figure.h"

#include <algorithm>
#include <cctype>
#include <numeric>

namespace df::render {
namespace {

Rgb side_color(const std::string& joint_name) {
  std::string n(joint_name);
  std::transform(n.begin(), n.end(), n.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (n.find("left") != std::string::npos) return {0.15, 0.35, 0.75};
  if (n.find("right") != std::string::npos) return {0.78, 0.2, 0.15};
  return {0.2, 0.2, 0.25};
}

}  // namespace

void draw_stick_figure(Canvas& canvas, const io::SkeletonFile& s, std::size_t t,
                       const Camera& camera, int x, int y, int w, int h, double margin) {
  std::vector<Eigen::Vector3d> p(s.joints);
  for (std::size_t j = 0; j < s.joints; ++j) {
    double q[3];
    s.joint(t, j, q);
    p[j] =
        camera.to_panel(Eigen::Vector3d(q[0], q[1], q[2]), w, h, margin) + Eigen::Vector3d(x, y, 0);
  }
  const double width = std::max(1.5, std::min(w, h) / 90.0), radius = width * 1.3;
  // Bones far to near (depth = mean of the two joints' view z; smaller is farther).
  std::vector<std::size_t> bones;
  for (std::size_t j = 0; j < s.joints; ++j)
    if (s.parents[j] >= 0) bones.push_back(j);
  std::stable_sort(bones.begin(), bones.end(), [&](std::size_t a, std::size_t b) {
    return p[a].z() + p[static_cast<std::size_t>(s.parents[a])].z() <
           p[b].z() + p[static_cast<std::size_t>(s.parents[b])].z();
  });
  canvas.push_clip(x, y, w, h);
  for (std::size_t j : bones) {
    const auto& q = p[static_cast<std::size_t>(s.parents[j])];
    canvas.line(q.x(), q.y(), p[j].x(), p[j].y(), width, side_color(s.joint_names[j]));
  }
  for (std::size_t j = 0; j < s.joints; ++j)
    canvas.disc(p[j].x(), p[j].y(), radius, {0.95, 0.55, 0.1});
  canvas.pop_clip();
}

}  // namespace df::render
