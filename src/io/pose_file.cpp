// Pose files (CONTRACT.md "Initial pose"): 16 numbers, a 4x4 row-major rigid transform.
#include <Eigen/SVD>
#include <cmath>
#include <cstdio>

#include "ewis/core/error.hpp"
#include "ewis/io/cloud_io.hpp"
#include "ewis/io/pose_file.hpp"
#include "file_bytes.hpp"
#include "text_scan.hpp"

namespace ewis {

Pose parse_pose(const std::string& text, const std::string& path) {
  double v[16];
  std::size_t n = 0, i = 0;
  // Separators: whitespace, commas, semicolons and brackets (so "[[1,0,0,0],...]" from JSON also reads).
  const auto sep = [](char c) {
    return io_detail::is_space(c) || c == ',' || c == ';' || c == '[' || c == ']';
  };
  while (i < text.size()) {
    while (i < text.size() && sep(text[i])) ++i;
    if (i == text.size()) break;
    if (text[i] == '#') {  // comment to the end of the line
      while (i < text.size() && text[i] != '\n') ++i;
      continue;
    }
    const std::size_t b = i;
    while (i < text.size() && !sep(text[i])) ++i;
    const std::string_view tok(text.data() + b, i - b);
    double d;
    if (!io_detail::parse_number(tok, d))
      throw InputError(path, "cannot read '" + io_detail::excerpt(tok) + "' as a number (expected 16 numbers)");
    if (!std::isfinite(d)) throw InputError(path, "pose matrix has a non-finite entry");
    if (n == 16) throw InputError(path, "more than 16 numbers (expected a 4x4 matrix)");
    v[n++] = d;
  }
  if (n != 16) throw InputError(path, "found " + std::to_string(n) + " numbers, expected 16 (a 4x4 matrix)");
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = v[4 * r + c];
  if (std::abs(m(3, 0)) > 1e-9 || std::abs(m(3, 1)) > 1e-9 || std::abs(m(3, 2)) > 1e-9 || std::abs(m(3, 3) - 1) > 1e-9)
    throw InputError(path, "last row of the pose must be 0 0 0 1");
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  const double ortho = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (ortho > 1e-3) throw InputError(path, "the rotation part is not orthonormal (scale or shear?)");
  if (r.determinant() < 0) throw InputError(path, "the rotation part is a reflection (determinant -1)");
  // Files carry a few decimals: snap the rotation to the nearest exact one so downstream math stays rigid.
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Pose pose = Pose::Identity();
  pose.linear() = svd.matrixU() * svd.matrixV().transpose();
  pose.translation() = m.topRightCorner<3, 1>();
  return pose;
}

Pose read_pose(const std::string& path) {
  const io_detail::FileBytes f = io_detail::read_file_bytes(path);
  return parse_pose(std::string(f.view()), path);
}

std::string pose_to_text(const Pose& pose) {
  const Eigen::Matrix4d m = pose.matrix();
  std::string out;
  char buf[64];
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      // %.17g round-trips every double; exact 0/1 print as "0"/"1".
      std::snprintf(buf, sizeof buf, "%.17g", m(r, c) == 0.0 ? 0.0 : m(r, c));
      out += buf;
      out += c < 3 ? ' ' : '\n';
    }
  }
  return out;
}

void write_pose(const Pose& pose, const std::string& path) { write_file_atomic(path, pose_to_text(pose)); }

}  // namespace ewis
