// libFuzzer target: the pose file (parse_pose). Anything but 16 finite numbers forming a rigid transform must
// end in ewis::InputError; an accepted pose is rigid and survives pose_to_text.
#include <cmath>
#include <cstdint>
#include <string>

#include "ewis/io/pose_file.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ewis::Pose pose;
  try {
    pose = ewis::parse_pose(text, "fuzz.txt");
  } catch (const ewis::InputError&) {
    return 0;
  }
  const Eigen::Matrix3d r = pose.linear();
  if (!pose.matrix().allFinite()) ewis_fuzz::broken("non-finite pose accepted");
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9) ewis_fuzz::broken("pose not rigid");
  if (std::abs(r.determinant() - 1.0) > 1e-9) ewis_fuzz::broken("pose determinant not 1");
  try {
    ewis::parse_pose(ewis::pose_to_text(pose), "roundtrip.txt");
  } catch (const ewis::InputError&) {
    ewis_fuzz::broken("pose_to_text wrote a pose that parse_pose refuses");
  }
  return 0;
}
