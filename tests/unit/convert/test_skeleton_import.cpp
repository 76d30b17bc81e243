// The skeleton importers on small hand-written fixtures (UTKinect, MSR-Action3D), BVH through
// assimp on a two-joint file with known positions, and skel2h5's processing steps.
#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "convert/bone_lengths.h"
#include "convert/skel2h5.h"
#include "convert/skeleton_import.h"
#include "helpers.h"
#include "synth/actions.h"

using namespace df;
using df::test::error_message;
using df::test::TempDir;
using df::test::write_text;

namespace {

// A UTKinect joints line: frame id, then joint j at (id + j, 2j, -j) / 100.
std::string utk_line(int id) {
  std::string s = std::to_string(id);
  for (int j = 0; j < 20; ++j)
    s += fmt::format(" {} {} {}", (id + j) / 100.0, 2 * j / 100.0, -j / 100.0);
  return s + "\n";
}

// MSR-Action3D's file order: the Kinect joint (io::kinect_joint_names) at each of its 20 lines.
constexpr int kMsrFromKinect[20] = {4,  8, 2,  1,  12, 16, 0,  5,  9,  6,
                                    10, 7, 11, 13, 17, 14, 18, 15, 19, 3};

// synth-actions' walkers (Kinect order; x to the figure's left, y up, facing +z) seen by a camera
// at the origin looking along +z, the figure 3 m away facing it: (x, y, z) -> (-x, y, 3 - z), a
// rotation (right-handed stays right-handed). `image`: then turned 180 degrees about z, as image
// coordinates (x right, y down, depth z) have it.
std::vector<std::vector<float>> camera_walkers(bool image) {
  synth::ActionParams p;
  p.classes = {};  // every class: walk, wave, jump, kick, squat
  p.per_class = 1;
  p.frames = 30;
  p.seed = 3;
  const io::SkeletonFile made = synth::make_actions(p);
  std::vector<std::vector<float>> out;
  for (std::size_t s = 0; s < made.sequences(); ++s) {
    std::vector<float> q(made.poses.begin() + made.offsets[s] * 60,
                         made.poses.begin() + made.offsets[s + 1] * 60);
    for (std::size_t k = 0; k < q.size(); k += 3) {
      const float x = -q[k], y = q[k + 1], z = 3 - q[k + 2];
      q[k] = image ? -x : x;
      q[k + 1] = image ? -y : y;
      q[k + 2] = z;
    }
    out.push_back(std::move(q));
  }
  return out;
}

// One MSR-Action3D file of Kinect-order frames: the file's 20 lines per frame in the dataset's
// order (or, `as_is`, in the Kinect order: what a reader that ignores the difference would need).
std::string msr_text(const std::vector<float>& kinect, bool as_is = false) {
  std::string text;
  for (std::size_t t = 0; t * 60 < kinect.size(); ++t)
    for (int line = 0; line < 20; ++line) {
      const std::size_t j =
          as_is ? static_cast<std::size_t>(line) : static_cast<std::size_t>(kMsrFromKinect[line]);
      const float* p = kinect.data() + t * 60 + j * 3;
      text += fmt::format("{} {} {} 1\n", p[0], p[1], p[2]);
    }
  return text;
}

}  // namespace

TEST_CASE("skeleton import: UTKinect segments by frame id, warnings for what can be skipped",
          "[convert]") {
  TempDir dir;
  std::string take;
  for (int id : {10, 12, 12, 14, 16, 18, 20}) take += utk_line(id);  // a repeated id is dropped
  write_text(dir / "joints_s03_e01.txt", take);
  write_text(dir / "actionLabel.txt",
             "s03_e01\nwalk: 12 16 \nwave: NaN NaN\nkick: 18 14\ns04_e01\nwalk: 1 5\n");
  const auto c = convert::read_utkinect(dir / "actionLabel.txt");
  REQUIRE(c.sequences.size() ==
          1);  // wave has no range, kick ends before it starts, s04 is missing
  const auto& s = c.sequences[0];
  CHECK(s.name == "s03_e01_walk");
  CHECK(s.label == "walk");
  CHECK(s.subject == 3);
  CHECK(s.times == std::vector<double>{12 / 30.0, 14 / 30.0, 16 / 30.0});
  CHECK(s.poses.size() == 3 * 60);
  CHECK(s.poses[60 + 3 * 5] == Approx((14 + 5) / 100.0));  // frame id 14, joint 5, x

  write_text(dir / "joints_s05_e01.txt", utk_line(1) + "2 0.1 0.2\n");
  write_text(dir / "bad.txt", "s05_e01\nwalk: 1 2\n");
  CHECK(error_message([&] { convert::read_utkinect(dir / "bad.txt"); }) ==
        "expected a frame id and 20 joints x (x y z) = 61 numbers, found 3 (" +
            (dir / "joints_s05_e01.txt") + ":2)");
  write_text(dir / "joints_s05_e01.txt", utk_line(1) + "2 0.1 x" + utk_line(3).substr(1));
  CHECK(error_message([&] {
          convert::read_utkinect(dir / "bad.txt");
        }).find("field 3 is not a finite number: 'x'") != std::string::npos);
  write_text(dir / "joints_s05_e01.txt", utk_line(1) + utk_line(2));
  write_text(dir / "bad.txt", "s05_e01\nwalk 1 2\n");
  CHECK(error_message([&] { convert::read_utkinect(dir / "bad.txt"); }) ==
        "expected a take 'sXX_eYY' or a segment 'class: start end' (" + (dir / "bad.txt") + ":2)");
}

TEST_CASE("skeleton import: MSR-Action3D files, 20 lines per frame, names give action and subject",
          "[convert]") {
  TempDir dir;
  std::string text;
  for (int f = 0; f < 3; ++f)
    for (int j = 0; j < 20; ++j) text += fmt::format("{} {} {} 1\n", f, j, 0.5);
  write_text(dir / "a14_s02_e03_skeleton3D.txt", text);
  const auto c = convert::read_msr_action3d({dir / "a14_s02_e03_skeleton3D.txt"});
  REQUIRE(c.sequences.size() == 1);
  CHECK(c.sequences[0].label == "forward_kick");
  CHECK(c.sequences[0].subject == 2);
  CHECK(c.sequences[0].times.size() == 3);
  CHECK(c.sequences[0].times[2] == Approx(2 / 15.0));
  // no side can be told from this geometry (shoulders level): joint 12 of the file (the chain
  // 1-8-10-12's hand) becomes hand_left
  CHECK(c.sequences[0].poses[(2 * 20 + 7) * 3 + 1] == 11);
  write_text(dir / "a01_s01_e01_skeleton3D.txt", text + "1 2 3 1\n");
  CHECK(error_message([&] { convert::read_msr_action3d({dir / "a01_s01_e01_skeleton3D.txt"}); }) ==
        "the last frame has 1 of 20 joint lines (" + (dir / "a01_s01_e01_skeleton3D.txt") + ":61)");
  write_text(dir / "a01_s01_e01_skeleton3D.txt", "1 2 3\n");
  CHECK(error_message([&] { convert::read_msr_action3d({dir / "a01_s01_e01_skeleton3D.txt"}); }) ==
        "expected 'x y z confidence', found 3 numbers (" + (dir / "a01_s01_e01_skeleton3D.txt") +
            ":1)");
  write_text(dir / "walk.txt", text);
  CHECK(error_message([&] {
          convert::read_msr_action3d({dir / "walk.txt"});
        }).find("not an MSR-Action3D skeleton file name") == 0);
}

TEST_CASE(
    "skeleton import: MSR-Action3D's joint order becomes the Kinect order, sides from the geometry",
    "[convert]") {
  for (const bool image : {false, true}) {
    TempDir dir;
    const auto walkers = camera_walkers(image);
    std::vector<std::string> files;
    for (std::size_t s = 0; s < walkers.size(); ++s) {
      files.push_back(dir / fmt::format("a{:02}_s01_e{:02}_skeleton3D.txt", s + 1, s + 1));
      write_text(files.back(), msr_text(walkers[s]));
    }
    const auto c = convert::read_msr_action3d(files);
    REQUIRE(c.sequences.size() == walkers.size());
    CHECK(c.joint_names == io::kinect_joint_names());
    for (std::size_t s = 0; s < walkers.size(); ++s) {
      REQUIRE(c.sequences[s].poses.size() == walkers[s].size());
      for (std::size_t k = 0; k < walkers[s].size(); ++k)
        REQUIRE(c.sequences[s].poses[k] == Approx(walkers[s][k]).margin(1e-5));
    }
    // the import's bones are the figure's: lengths constant, well inside the default tolerance
    const auto bones = convert::bone_length_spread(c);
    REQUIRE(bones.size() == 19);
    CHECK(bones.front().typical < 0.01);
  }
}

TEST_CASE("bone-length check: a shuffled joint order fails it, a right one passes", "[convert]") {
  const auto walkers = camera_walkers(false);
  convert::RawSkeletonCollection c;
  c.joint_names = io::kinect_joint_names();
  c.parents = io::kinect_joint_parents();
  for (std::size_t s = 0; s < walkers.size(); ++s)
    c.sequences.push_back(
        {fmt::format("walker{}", s), "walk", 1, std::vector<double>(30), walkers[s]});
  CHECK_NOTHROW(convert::check_bone_lengths(c, 0.3, true, "walkers"));
  // the file read in the wrong order: MSR-Action3D's lines taken as Kinect joints
  convert::RawSkeletonCollection shuffled = c;
  for (auto& s : shuffled.sequences)
    for (std::size_t t = 0; t * 60 < s.poses.size(); ++t)
      for (std::size_t j = 0; j < 20; ++j)
        for (std::size_t d = 0; d < 3; ++d)
          s.poses[t * 60 + j * 3 + d] =
              c.sequences[&s - shuffled.sequences.data()]
                  .poses[t * 60 + static_cast<std::size_t>(kMsrFromKinect[j]) * 3 + d];
  const auto bones = convert::bone_length_spread(shuffled);
  CHECK(bones.front().typical > 0.3);
  const std::string e =
      error_message([&] { convert::check_bone_lengths(shuffled, 0.3, true, "walkers"); });
  CHECK(e.find("bones change length within a recording by more than --bone-tolerance 0.3") !=
        std::string::npos);
  CHECK(e.find(bones.front().name) != std::string::npos);
  CHECK(e.find("is the joint order right") != std::string::npos);
  CHECK_NOTHROW(convert::check_bone_lengths(shuffled, 0.3, false, "walkers"));  // a warning only
}

TEST_CASE("skel2h5: a directory of MSR-Action3D files imports as it is, other files left out",
          "[convert]") {
  TempDir dir;
  const auto walkers = camera_walkers(false);
  std::filesystem::create_directory(dir / "msr");
  for (std::size_t s = 0; s < walkers.size(); ++s)
    write_text(dir / fmt::format("msr/a{:02}_s{:02}_e01_skeleton3D.txt", s % 2 + 1, s + 1),
               msr_text(walkers[s]));
  write_text(dir / "msr/readme.txt", "the dataset's notes\n");
  convert::Skel2h5Options opt;
  opt.inputs = {dir / "msr"};
  opt.output = dir / "m.h5";
  opt.normalize = false;
  CommonOptions common;
  convert::skel2h5(opt, common);
  const io::SkeletonFile f = io::read_skeleton_file(dir / "m.h5");
  CHECK(f.sequences() == walkers.size());
  CHECK(f.sequence_names[0] == "a01_s01_e01");
  CHECK(f.joint_names == io::kinect_joint_names());
  CHECK(f.poses[3 * 3 + 1] == Approx(walkers[0][3 * 3 + 1]));  // the head

  // the same files in Kinect order under MSR names: --strict stops the import
  for (std::size_t s = 0; s < walkers.size(); ++s)
    write_text(dir / fmt::format("msr/a{:02}_s{:02}_e01_skeleton3D.txt", s % 2 + 1, s + 1),
               msr_text(walkers[s], true));
  opt.strict = true;
  opt.output = dir / "bad.h5";
  CHECK(error_message([&] { convert::skel2h5(opt, common); }).find("is the joint order right") !=
        std::string::npos);
  CHECK(!std::filesystem::exists(dir / "bad.h5"));
  std::filesystem::remove_all(dir / "msr");
  std::filesystem::create_directory(dir / "msr");
  write_text(dir / "msr/readme.txt", "notes\n");
  CHECK(error_message([&] { convert::skel2h5(opt, common); }).find("cannot tell the format") == 0);
}

TEST_CASE("skeleton import: BVH forward kinematics through assimp", "[convert]") {
  TempDir dir;
  // Root at (1, 2, 3) then (1, 2, 4); a child 1 along x, rotated 90 deg about z in frame 2.
  write_text(dir / "two.bvh",
             "HIERARCHY\n"
             "ROOT Hips\n"
             "{\n"
             "  OFFSET 0 0 0\n"
             "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
             "  JOINT Arm\n"
             "  {\n"
             "    OFFSET 1 0 0\n"
             "    CHANNELS 3 Zrotation Xrotation Yrotation\n"
             "    End Site\n"
             "    {\n"
             "      OFFSET 1 0 0\n"
             "    }\n"
             "  }\n"
             "}\n"
             "MOTION\n"
             "Frames: 2\n"
             "Frame Time: 0.1\n"
             "1 2 3 0 0 0 0 0 0\n"
             "1 2 4 90 0 0 0 0 0\n");
  const auto c = convert::read_bvh({dir / "two.bvh"}, "test");
  REQUIRE(c.sequences.size() == 1);
  CHECK(c.frame_rate == Approx(10));
  const auto& s = c.sequences[0];
  CHECK(s.label == "test");
  REQUIRE(s.times.size() == 2);
  const std::size_t J = c.joints();
  REQUIRE(J >= 3);
  auto joint = [&](std::size_t f, const std::string& name) {
    const auto j = static_cast<std::size_t>(
        std::find(c.joint_names.begin(), c.joint_names.end(), name) - c.joint_names.begin());
    REQUIRE(j < J);
    return std::array<double, 3>{s.poses[(f * J + j) * 3], s.poses[(f * J + j) * 3 + 1],
                                 s.poses[(f * J + j) * 3 + 2]};
  };
  CHECK(joint(0, "Hips")[2] == Approx(3));
  CHECK(joint(1, "Hips")[2] == Approx(4));
  CHECK(joint(0, "Arm")[0] == Approx(2));  // 1 + offset 1 along x
  // frame 2: the root turned 90 deg about z, so the arm's offset (1, 0, 0) points along +y
  CHECK(joint(1, "Arm")[0] == Approx(1).margin(1e-5));
  CHECK(joint(1, "Arm")[1] == Approx(3));
  write_text(dir / "junk.bvh", "HIERARCHY\nROOT\n");
  CHECK(error_message([&] {
          convert::read_bvh({dir / "junk.bvh"}, "");
        }).find("not a readable BVH file") == 0);
}

TEST_CASE("skel2h5: resampling, per-class split, clips, normalization from the training part",
          "[convert]") {
  synth::ActionParams p;
  p.classes = {"walk", "wave"};
  p.per_class = 10;
  p.frames = 40;
  p.seed = 4;
  io::SkeletonFile made = synth::make_actions(p);
  convert::RawSkeletonCollection c;
  c.joint_names = made.joint_names;
  c.parents = made.parents;
  c.frame_rate = 30;
  for (std::size_t s = 0; s < made.sequences(); ++s) {
    convert::RawSkeletonSequence q;
    q.label = made.class_names[static_cast<std::size_t>(made.labels[s])];
    q.subject = made.subjects[s];
    q.name = made.sequence_names[s];
    for (int t = 0; t < 40; ++t) q.times.push_back(t / 30.0);
    q.poses.assign(made.poses.begin() + made.offsets[s] * 60,
                   made.poses.begin() + made.offsets[s + 1] * 60);
    c.sequences.push_back(q);
  }
  // 30 -> 15 fps keeps every other frame exactly; 40 frames span 39/30 s -> 20 frames
  convert::RawSkeletonCollection half = c;
  convert::resample(half, 15);
  CHECK(half.sequences[0].times.size() == 20);
  CHECK(half.sequences[0].poses[5 * 60 + 7] == Approx(c.sequences[0].poses[10 * 60 + 7]));
  convert::RawSkeletonCollection same = c;
  convert::resample(same, 30);
  CHECK(same.sequences[3].poses == c.sequences[3].poses);

  convert::Skel2h5Options opt;
  opt.test_fraction = 0.3;
  const auto test = convert::assign_test_split(c, opt, 7);
  CHECK(std::count(test.begin(), test.begin() + 10, 1) == 3);  // 3 of each class's 10
  CHECK(std::count(test.begin() + 10, test.end(), 1) == 3);
  CHECK(convert::assign_test_split(c, opt, 7) == test);
  CHECK(convert::assign_test_split(c, opt, 8) != test);
  opt.test_fraction = 0;
  opt.test_subjects = {2};
  const auto by_subject = convert::assign_test_split(c, opt, 7);
  for (std::size_t s = 0; s < c.sequences.size(); ++s)
    CHECK(by_subject[s] == (c.sequences[s].subject == 2));

  opt.length = 16;
  opt.clip_stride = 8;
  const io::SkeletonFile f = convert::build_skeleton_file(c, test, opt);
  CHECK(f.sequences() == 20 * 4);  // starts 0, 8, 16, 24 of 40 frames
  CHECK(f.sequence_names[1] == c.sequences[0].name + "#1");
  CHECK(f.test[4 * 2] == test[2]);
  // training clips: every coordinate has mean 0 and s.d. 1 (the root joint's stay 0)
  const auto& n = f.normalization;
  REQUIRE(n.present());
  for (std::size_t k : {std::size_t{19}, std::size_t{41}}) {  // wrist_left y, knee_left z
    double sum = 0, sq = 0, count = 0;
    for (std::size_t s = 0; s < f.sequences(); ++s) {
      if (f.test[s]) continue;
      for (auto t = f.offsets[s]; t < f.offsets[s + 1]; ++t) {
        const double v = f.poses[static_cast<std::size_t>(t) * 60 + k];
        sum += v;
        sq += v * v;
        ++count;
      }
    }
    CHECK(sum / count == Approx(0).margin(1e-4));
    CHECK(sq / count == Approx(1).epsilon(1e-3));
  }
  // de-normalized: the source's pose minus its root
  const auto raw = f.raw_poses();
  const float* src = c.sequences[0].poses.data() + 8 * 60;  // clip 1 starts at frame 8
  const float* got = raw.data() + 16 * 60;
  for (int k = 0; k < 60; ++k) CHECK(got[k] == Approx(src[k] - src[k % 3]).margin(1e-5));

  // --sd-floor: each s.d. below the floor is raised to it, the others and the mean stay, the
  // root's stays 1, and the poses still de-normalize to the source's
  std::vector<double> sds(n.std.begin() + 3, n.std.end());  // (the root joint's are 1)
  std::sort(sds.begin(), sds.end());
  const double floor = sds[sds.size() / 2];  // half the coordinates lie below it
  opt.sd_floor = floor;
  const io::SkeletonFile g = convert::build_skeleton_file(c, test, opt);
  const auto& m = g.normalization;
  int raised = 0;
  for (std::size_t k = 0; k < 60; ++k) {
    CHECK(m.mean[k] == n.mean[k]);
    if (k < 3) {
      CHECK(m.std[k] == 1);
      continue;
    }
    CHECK(m.std[k] == std::max(n.std[k], floor));
    raised += n.std[k] < floor;
  }
  CHECK(raised >= 20);
  const auto raw_floored = g.raw_poses();
  for (std::size_t k = 0; k < raw.size(); k += 97)
    CHECK(raw_floored[k] == Approx(raw[k]).margin(1e-5));
}
