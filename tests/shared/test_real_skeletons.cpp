// Skeleton import on real Kinect recordings (UTKinect-Action3D, label shared-data): its takes
// written out as MSR-Action3D files (the dataset's own joint order, 20 lines per frame) import
// back to the same joints in the Kinect order, left and right told from the geometry alone; the
// takes in the Kinect order under MSR names, read in MSR's order (a wrong order, as the import's
// reading MSR's files in the Kinect order was) fail the bone-length check at the default
// tolerance, and the right order passes it.
#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "convert/bone_lengths.h"
#include "convert/skel2h5.h"
#include "convert/skeleton_import.h"
#include "helpers.h"

namespace fs = std::filesystem;
using namespace df;

namespace {

// MSR-Action3D's file order: the Kinect joint at each of its 20 lines.
constexpr int kMsrFromKinect[20] = {4,  8, 2,  1,  12, 16, 0,  5,  9,  6,
                                    10, 7, 11, 13, 17, 14, 18, 15, 19, 3};
const double kDefaultTolerance = convert::Skel2h5Options{}.bone_tolerance;

// Every UTKinect take: its frames' 20 joints (x y z), Kinect order, as the file prints them.
std::vector<std::vector<std::string>> utkinect_takes() {
  const char* root = std::getenv("DF_SHARED_DATA");
  REQUIRE(root != nullptr);
  const fs::path dir = fs::path(root) / "UTKinect" / "UTKinect" / "joints";
  REQUIRE(fs::is_directory(dir));
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind("joints_", 0) == 0) files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  std::vector<std::vector<std::string>> takes;
  for (const auto& f : files) {
    std::ifstream in(f);
    std::vector<std::string> frames;
    for (std::string line; std::getline(in, line);) {
      std::istringstream words(line);
      std::vector<std::string> v{std::istream_iterator<std::string>(words), {}};
      if (v.size() != 61) continue;
      frames.emplace_back();
      for (std::size_t k = 1; k < 61; ++k) frames.back() += v[k] + (k % 3 ? " " : "\n");
    }
    takes.push_back(frames);
  }
  return takes;
}

// The take as an MSR-Action3D file: per frame 20 lines "x y z 1", in MSR's order or as they are.
std::string msr_file(const std::vector<std::string>& frames, bool msr_order) {
  std::string text;
  for (const auto& f : frames) {
    std::istringstream lines(f);
    std::vector<std::string> joint;
    for (std::string l; std::getline(lines, l);) joint.push_back(l);
    for (std::size_t line = 0; line < 20; ++line)
      text += joint[msr_order ? static_cast<std::size_t>(kMsrFromKinect[line]) : line] + " 1\n";
  }
  return text;
}

}  // namespace

TEST_CASE("real data: UTKinect's takes as MSR-Action3D files import to the Kinect joints",
          "[shared-data]") {
  const auto takes = utkinect_takes();
  REQUIRE(takes.size() == 20);
  test::TempDir dir;
  std::vector<std::string> files, shuffled;
  fs::create_directory(dir / "misread");
  for (std::size_t t = 0; t < takes.size(); ++t) {
    const std::string name = fmt::format("a01_s{:02}_e{:02}_skeleton3D.txt", t / 2 + 1, t % 2 + 1);
    files.push_back(dir / name);
    test::write_text(files.back(), msr_file(takes[t], true));
    shuffled.push_back((fs::path(dir / "misread") / name).string());
    test::write_text(shuffled.back(), msr_file(takes[t], false));
  }
  const auto c = convert::read_msr_action3d(files);
  REQUIRE(c.sequences.size() == takes.size());
  CHECK(c.joint_names == io::kinect_joint_names());
  for (std::size_t t = 0; t < takes.size(); ++t) {
    std::string kinect;
    const auto& p = c.sequences[t].poses;
    REQUIRE(p.size() == takes[t].size() * 60);
    for (std::size_t f = 0; f < takes[t].size(); ++f) {
      std::istringstream expected(takes[t][f]);
      for (std::size_t k = 0; k < 60; ++k) {
        double x = 0;
        expected >> x;
        REQUIRE(p[f * 60 + k] == static_cast<float>(x));
      }
    }
  }
  CHECK(convert::bone_length_spread(c).front().typical < kDefaultTolerance);
  CHECK_NOTHROW(convert::check_bone_lengths(c, kDefaultTolerance, true, "utkinect-as-msr"));

  // files holding the Kinect order under MSR names, read as MSR's order: the joints land wrongly
  // (the mirror of the old import, which read MSR's order as the Kinect's), the check names bones
  const auto misread = convert::read_msr_action3d(shuffled);
  const auto bones = convert::bone_length_spread(misread);
  CHECK(bones.front().typical > 0.4);
  const std::string e = test::error_message(
      [&] { convert::check_bone_lengths(misread, kDefaultTolerance, true, "misread"); });
  CHECK(e.find("is the joint order right for this format?") != std::string::npos);
}
