// Is a scan in its sensor's frame: a one-shot scan is a depth image from its sensor, and not from elsewhere.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "ewis/register/sensor_origin.hpp"

namespace ewis {
namespace {

// In the sensor frame (at the origin, looking along +z), one point per pixel ray (1 mrad): a floor at depth 700, a
// 200 x 200 mm plate at 600 and a 60 x 60 mm block on it at 550, with 0.3 mm noise and 3 % of outliers spread
// through the view (what outlier removal leaves).
std::vector<Eigen::Vector3f> depth_image(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> noise(0.0f, 0.3f);
  std::vector<Eigen::Vector3f> pts;
  for (int i = -250; i <= 250; ++i)
    for (int j = -250; j <= 250; ++j) {
      const Eigen::Vector3f ray(0.001f * static_cast<float>(i), 0.001f * static_cast<float>(j), 1.0f);
      float depth = 700.0f;
      if (std::abs(ray.x() * 600.0f) <= 100.0f && std::abs(ray.y() * 600.0f) <= 100.0f) depth = 600.0f;
      if (std::abs(ray.x() * 550.0f - 20.0f) <= 30.0f && std::abs(ray.y() * 550.0f) <= 30.0f) depth = 550.0f;
      pts.push_back(ray * (depth + noise(rng)));
    }
  std::uniform_real_distribution<float> u(-0.25f, 0.25f), z(300.0f, 900.0f);
  const std::size_t outliers = pts.size() * 3 / 100;
  for (std::size_t k = 0; k < outliers; ++k) {
    const float d = z(rng);
    pts.emplace_back(u(rng) * d, u(rng) * d, d);
  }
  return pts;
}

std::vector<Eigen::Vector3f> moved(std::vector<Eigen::Vector3f> pts, const Pose& T) {
  for (Eigen::Vector3f& p : pts) p = (T * p.cast<double>()).cast<float>();
  return pts;
}

TEST(SensorOrigin, AScanInItsSensorsFrameIsADepthImageFromItsOrigin) {
  const double f = occluded_from_origin(depth_image(1));
  EXPECT_LT(f, 0.05);  // the outliers behind the surfaces
  EXPECT_LE(f, kNotSensorFrameFraction);
}

TEST(SensorOrigin, AScanSavedInAnotherFrameIsNot) {
  // The same scan in a robot's frame: turned 100 deg and moved so that the scene lies about that frame's origin.
  Pose T = Pose::Identity();
  T.linear() = Eigen::AngleAxisd(100.0 * M_PI / 180.0, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T.translation() = -(T.linear() * Eigen::Vector3d(0, 0, 650)) + Eigen::Vector3d(-50, 80, 30);
  EXPECT_GT(occluded_from_origin(moved(depth_image(2), T)), kNotSensorFrameFraction);
  // As in a CAD's frame: the origin at the scene's centre, the view's axis along the new y. Nearly every point lies
  // behind another along its ray (measured along z instead, rays near the origin's plane read 96-97 %: real scenes
  // in CAD coordinates then fell from 99.5 % to 59-65 %).
  Pose cad = Pose::Identity();
  cad.linear() = Eigen::AngleAxisd(M_PI / 2.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  cad.translation() = -(cad.linear() * Eigen::Vector3d(0, 0, 650));
  EXPECT_GT(occluded_fraction(moved(depth_image(7), cad), Pose::Identity()), 0.99);
}

TEST(SensorOrigin, SeenFromBesideTheSceneSurfacesHideEachOther) {
  const std::vector<Eigen::Vector3f> pts = depth_image(4);
  const double right = occluded_fraction(pts, Pose::Identity());
  // From a sensor 30 deg and 60 deg off, looking at the scene's centre: the block and the plate's edges stand in
  // front of floor points.
  for (double deg : {30.0, 60.0}) {
    const Eigen::AngleAxisd r(deg * M_PI / 180.0, Eigen::Vector3d::UnitY());
    Pose beside = Pose::Identity();
    beside.linear() = r.toRotationMatrix();
    beside.translation() = Eigen::Vector3d(0, 0, 650) - r.toRotationMatrix() * Eigen::Vector3d(0, 0, 650);
    const double f = occluded_fraction(pts, beside);
    EXPECT_GT(f, right + 0.1) << deg;  // 16 % and 15 %: the limit of the test (why a threshold of 50 %)
  }
  EXPECT_LT(right, 0.05);
}

TEST(SensorOrigin, ADepthImageTurnedOverInFrontOfTheOriginPasses) {
  // The known blind spot: turned over (180 deg about x) and pushed 1300 mm along z, the scan lies in front of the
  // origin and is nearly a depth image from there, seen from behind its surfaces.
  Pose T = Pose::Identity();
  T.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0, 0, 1300);
  EXPECT_LE(occluded_from_origin(moved(depth_image(5), T)), kNotSensorFrameFraction);
}

// The camera conventions: the contract's (z forward, y down), OpenGL's (-z forward, y up) and a ROS body frame (x
// forward, y left, z up); each turned back into the contract's frame is the depth image again.
TEST(SensorOrigin, TheCameraConventionIsReadAndTurnedBack) {
  const std::vector<Eigen::Vector3f> image = depth_image(3);
  const ScanConvention given = scan_convention(image);
  EXPECT_STREQ(given.looks_along, "+z");
  EXPECT_TRUE(given.turn.isIdentity());
  const Eigen::Matrix3f gl = Eigen::Vector3f(1, -1, -1).asDiagonal();
  Eigen::Matrix3f body;
  body << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // x_body = z, y_body = -x, z_body = -y
  for (const auto& [name, to] : {std::pair<const char*, Eigen::Matrix3f>{"-z", gl}, {"+x", body}}) {
    std::vector<Eigen::Vector3f> written(image.size());
    for (std::size_t i = 0; i < image.size(); ++i) written[i] = to * image[i];
    const ScanConvention c = scan_convention(written);
    EXPECT_STREQ(c.looks_along, name);
    EXPECT_GT(occluded_from_origin(written), kNotSensorFrameFraction) << name;  // as written: no depth image
    EXPECT_TRUE(c.turn.isApprox((to.transpose()).cast<double>())) << name;
    std::vector<Eigen::Vector3f> back(written.size());
    for (std::size_t i = 0; i < written.size(); ++i) back[i] = c.turn.cast<float>() * written[i];
    EXPECT_LT(occluded_from_origin(back), 0.3) << name;
    EXPECT_NEAR(occluded_from_origin(written, c), occluded_from_origin(back), 0.01) << name;  // without turning
  }
}

}  // namespace
}  // namespace ewis
