#pragma once
// Shared by the three step programs: a monotonic timer, the one-line JSON they print, and what every side must
// use identically (the ICP distance schedule, the straight tube's truth, the pinhole rays, pose errors), so the
// rows compare the same work with the same parameters. No ewis, PCL or Open3D types here: Eigen only.
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace steps {

struct Timer {
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  double ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
};

// {"step": ..., "ms": ..., "result": ..., "detail": "..."}: `result` is the number compared for agreement.
inline void print(const std::string& step, double ms, double result, const std::string& detail = "") {
  std::printf("{\"step\": \"%s\", \"ms\": %.3f, \"result\": %.6f, \"detail\": \"%s\"}\n", step.c_str(), ms, result,
              detail.c_str());
}

inline int usage(const char* prog) {
  std::fprintf(stderr,
               "usage: %s STEP ARGS, STEP one of\n"
               "  read FILE | resolution FILE | ror FILE RADIUS K | voxel FILE LEAF | cluster FILE TOL |\n"
               "  sample MESH N                          (ewis, Open3D)\n"
               "  icp SOURCE TARGET INIT_POSE TRUTH_POSE (point-to-plane; TARGET has normals)\n"
               "  cylinder TUBE_PLY                      (straight tube of steps::kTube; ewis, PCL)\n"
               "  raycast MESH CAMERA_POSE               (1280x1024, hfov 58 deg; ewis, Open3D)\n"
               "  chain SCAN CAD_CABLE_PLY RADIUS POSE   (one cable from its CAD samples, CAD frame; ewis, PCL)\n"
               "  inspect DATA_DIR                       (the whole inspection; ewis, PCL)\n"
               "helpers (ewis_steps only): convert-pcd IN OUT | prepare SCENE_DIR FILTERED_PLY OUT_DIR\n",
               prog);
  return 2;
}

// "key=value" for a detail string, with a fixed number of decimals.
inline std::string kv(const std::string& key, double value, int decimals = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  return key + "=" + buf;
}

// ---- poses ------------------------------------------------------------------------------------------------

// 16 numbers, a row-major 4x4 (the project's pose.txt format).
inline Eigen::Matrix4d read_matrix4(const std::string& path) {
  std::ifstream in(path);
  Eigen::Matrix4d m;
  for (int i = 0; i < 16; ++i)
    if (!(in >> m(i / 4, i % 4))) throw std::runtime_error("cannot read a 4x4 matrix from " + path);
  return m;
}

// Rotation angle (deg) between two poses, and how far apart they put `at_mm` (a point of the source: the
// translation error where the data is, not at the sensor 600 mm away).
struct PoseError {
  double rotation_deg = 0, translation_mm = 0;
};
inline PoseError pose_error(const Eigen::Matrix4d& estimate, const Eigen::Matrix4d& truth,
                            const Eigen::Vector3d& at_mm) {
  const Eigen::Matrix3d dr = estimate.topLeftCorner<3, 3>().transpose() * truth.topLeftCorner<3, 3>();
  const double c = std::clamp((dr.trace() - 1.0) / 2.0, -1.0, 1.0);
  const Eigen::Vector3d a = estimate.topLeftCorner<3, 3>() * at_mm + estimate.topRightCorner<3, 1>();
  const Eigen::Vector3d b = truth.topLeftCorner<3, 3>() * at_mm + truth.topRightCorner<3, 1>();
  return {std::acos(c) * 180.0 / M_PI, (a - b).norm()};
}

// ---- ICP row ----------------------------------------------------------------------------------------------
// Every side runs the same correspondence-distance schedule (ewis's: from 3 x the expected error halving down
// to the final distance, = spacing 1 mm + 3 x noise 0.2 mm as `ewis inspect` uses), at most
// kIcpIterationsPerStage iterations per stage, each stage starting from the last one's pose.
inline constexpr double kIcpFirstDistanceMm = 45.0;  // 3 x the 15 mm initial error
inline constexpr double kIcpFinalDistanceMm = 1.6;
inline constexpr int kIcpIterationsPerStage = 30;
inline constexpr double kIcpNoiseMm = 0.2;
inline std::vector<double> icp_schedule_mm(double first_mm = kIcpFirstDistanceMm) {
  std::vector<double> out;
  for (double d = first_mm; d > kIcpFinalDistanceMm * 1.0001; d *= 0.5) out.push_back(d);
  out.push_back(kIcpFinalDistanceMm);
  return out;
}

// The common yardstick of the ICP results (each side's own figures differ in definition): over every source
// point whose nearest target point (by the side's own k-d tree) lies within the final distance, the RMS
// point-to-plane residual; fitness = that count / all.
struct IcpFit {
  double rmse_mm = 0, fitness = 0;
};
// nearest(p, q, n): the nearest target point q and its normal n; false when none.
template <class Nearest>
IcpFit icp_fit(const std::vector<Eigen::Vector3d>& source, const Eigen::Matrix4d& pose, Nearest nearest) {
  double sum = 0;
  std::size_t count = 0;
  for (const Eigen::Vector3d& s : source) {
    const Eigen::Vector3d p = pose.topLeftCorner<3, 3>() * s + pose.topRightCorner<3, 1>();
    Eigen::Vector3d q, n;
    if (!nearest(p, q, n) || (p - q).norm() > kIcpFinalDistanceMm) continue;
    const double r = n.dot(p - q);
    sum += r * r;
    ++count;
  }
  return {count ? std::sqrt(sum / count) : 0.0, source.empty() ? 0.0 : double(count) / source.size()};
}

inline Eigen::Vector3d centroid(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : points) c += p;
  return points.empty() ? c : Eigen::Vector3d(c / double(points.size()));
}

inline std::string icp_detail(const Eigen::Matrix4d& pose, const Eigen::Matrix4d& truth,
                              const std::vector<Eigen::Vector3d>& source, const IcpFit& fit, int iterations) {
  const PoseError e = pose_error(pose, truth, centroid(source));
  return kv("rot_deg", e.rotation_deg, 4) + " " + kv("trans_mm", e.translation_mm, 3) + " " +
         kv("rmse_mm", fit.rmse_mm, 4) + " " + kv("fitness", fit.fitness, 4) +
         (iterations >= 0 ? " iterations=" + std::to_string(iterations) : "");
}

// ---- cylinder row: the simulated straight tube (written once by `ewis_steps prepare`) -----------------------
// Sensor at the origin looking along +z (a scan in its sensor's frame), the tube 600 mm away, its axis oblique.
struct StraightTube {
  Eigen::Vector3d center_mm{15.0, -10.0, 600.0};
  Eigen::Vector3d axis = Eigen::Vector3d(0.8, 0.55, 0.24).normalized();
  double radius_mm = 5.0;
  double length_mm = 120.0;
  double noise_mm = 0.2;             // Gaussian, along the sensor's ray
  int surface_points = 15000;        // on the side the sensor sees
  double outlier_fraction = 0.4;     // of all points, uniform in the surface points' bounding box
  unsigned seed = 8;
};
inline const StraightTube kTube{};

// Angle (deg) between a fitted axis and the truth, the fitted axis line's distance from the truth's centre
// (mm), and the radius error (mm).
inline std::string cylinder_detail(const Eigen::Vector3d& point, const Eigen::Vector3d& axis, double radius_mm) {
  const Eigen::Vector3d a = axis.normalized();
  const double angle = std::acos(std::min(1.0, std::abs(a.dot(kTube.axis)))) * 180.0 / M_PI;
  const Eigen::Vector3d d = kTube.center_mm - point;
  const double offset = (d - d.dot(a) * a).norm();
  return kv("radius_err_mm", radius_mm - kTube.radius_mm, 3) + " " + kv("axis_deg", angle, 3) + " " +
         kv("axis_offset_mm", offset, 3);
}

// ---- ray casting row: CONTRACT.md's pinhole (square pixels, principal point at the centre, z forward,
// x right, y down), one ray through each pixel centre, unit directions so hit distances are in mm ------------
inline constexpr int kImageWidthPx = 1280, kImageHeightPx = 1024;
inline constexpr double kImageHfovDeg = 58.0;
inline Eigen::Vector3d pixel_direction_camera(int col, int row) {
  const double f = (kImageWidthPx / 2.0) / std::tan(kImageHfovDeg * M_PI / 360.0);
  return Eigen::Vector3d((col + 0.5 - kImageWidthPx / 2.0) / f, (row + 0.5 - kImageHeightPx / 2.0) / f, 1.0)
      .normalized();
}

// ---- chain row -------------------------------------------------------------------------------------------
// Least-squares line through points (centroid, principal direction).
inline void fit_line(const std::vector<Eigen::Vector3d>& points, Eigen::Vector3d& point, Eigen::Vector3d& dir) {
  point = centroid(points);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points) cov += (p - point) * (p - point).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  dir = es.eigenvectors().col(2);
}

}  // namespace steps
