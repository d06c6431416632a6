#pragma once
// The one point-cloud type of the project (DESIGN.md "Data"): positions in mm, optional
// per-point attributes in parallel vectors of the same length (empty when absent).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ewis {

using Rgb = std::array<std::uint8_t, 3>;

// A named per-point scalar that is not a position, normal, colour or intensity
// (e.g. "curvature", "confidence"): carried through filters so writers keep it.
struct ScalarField {
  std::string name;
  std::vector<float> values;
};

struct Cloud {
  std::vector<Eigen::Vector3f> points;   // mm
  std::vector<Eigen::Vector3f> normals;  // unit length, or empty
  std::vector<Rgb> colors;               // or empty
  std::vector<float> intensities;        // or empty
  std::vector<ScalarField> scalars;      // other fields, each values.size() == points.size()

  std::size_t size() const { return points.size(); }
  bool empty() const { return points.empty(); }
  bool has_normals() const { return !normals.empty(); }
  bool has_colors() const { return !colors.empty(); }
  bool has_intensities() const { return !intensities.empty(); }
};

// The values at `indices`, in that order (empty stays empty).
template <class T>
std::vector<T> pick(const std::vector<T>& values, const std::vector<std::uint32_t>& indices) {
  std::vector<T> out;
  if (values.empty()) return out;
  out.reserve(indices.size());
  for (auto i : indices) out.push_back(values[i]);
  return out;
}

// The points (and every attribute) at `indices`, in that order.
Cloud select(const Cloud& cloud, const std::vector<std::uint32_t>& indices);

// At most max_count indices of [0, n), evenly strided (index floor(i x n / max_count)); all of them when n <=
// max_count or max_count is 0. In a sensor's raster order this is an even spread over the image.
std::vector<std::uint32_t> evenly_strided(std::size_t n, std::size_t max_count);

// Axis-aligned bounds; false when the cloud is empty.
bool bounds(const std::vector<Eigen::Vector3f>& points, Eigen::Vector3f& min_out, Eigen::Vector3f& max_out);

// Multiplies positions by `factor` (unit conversion); normals are unchanged.
void scale(Cloud& cloud, float factor);

}  // namespace ewis
