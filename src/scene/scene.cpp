// Scene bookkeeping: element lookup, appending elements, per-element statistics.
#include "ewis/scene/scene.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <limits>

namespace ewis {

int Scene::find(const std::string& name) const {
  for (std::size_t i = 0; i < elements.size(); ++i)
    if (elements[i].name == name) return static_cast<int>(i);
  return -1;
}

namespace {

void compute_stats(const Scene& scene, Element& e) {
  double area = 0.0;
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  const std::size_t end = std::size_t(e.first_triangle) + e.triangle_count;
  for (std::size_t t = e.first_triangle; t < end; ++t) {
    const Eigen::Vector3i& tri = scene.triangles[t];
    const Eigen::Vector3d a = scene.vertices[tri[0]].cast<double>();
    const Eigen::Vector3d b = scene.vertices[tri[1]].cast<double>();
    const Eigen::Vector3d c = scene.vertices[tri[2]].cast<double>();
    const double ta = 0.5 * (b - a).cross(c - a).norm();
    area += ta;
    weighted += ta * (a + b + c) / 3.0;
    lo = lo.cwiseMin(a).cwiseMin(b).cwiseMin(c);
    hi = hi.cwiseMax(a).cwiseMax(b).cwiseMax(c);
  }
  e.area_mm2 = area;
  if (e.triangle_count == 0) {
    e.center_of_mass = e.bounds_min = e.bounds_max = Eigen::Vector3d::Zero();
    return;
  }
  e.center_of_mass = area > 0 ? Eigen::Vector3d(weighted / area) : Eigen::Vector3d(0.5 * (lo + hi));
  e.bounds_min = lo;
  e.bounds_max = hi;
}

}  // namespace

void add_element(Scene& scene, const std::string& name, const std::vector<Eigen::Vector3f>& vertices,
                 const std::vector<Eigen::Vector3i>& triangles) {
  const int offset = static_cast<int>(scene.vertices.size());
  scene.vertices.insert(scene.vertices.end(), vertices.begin(), vertices.end());
  int index = scene.find(name);
  if (index < 0) {
    Element e;
    e.name = name;
    e.first_triangle = static_cast<std::uint32_t>(scene.triangles.size());
    scene.elements.push_back(e);
    index = static_cast<int>(scene.elements.size()) - 1;
  }
  Element& e = scene.elements[index];
  // Insert at the end of the element's range so its triangles stay contiguous; later elements shift.
  const std::size_t at = std::size_t(e.first_triangle) + e.triangle_count;
  std::vector<Eigen::Vector3i> shifted(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) shifted[i] = triangles[i].array() + offset;
  scene.triangles.insert(scene.triangles.begin() + at, shifted.begin(), shifted.end());
  scene.triangle_element.insert(scene.triangle_element.begin() + at, triangles.size(),
                                static_cast<std::uint32_t>(index));
  e.triangle_count += static_cast<std::uint32_t>(triangles.size());
  for (std::size_t i = index + 1; i < scene.elements.size(); ++i)
    scene.elements[i].first_triangle += static_cast<std::uint32_t>(triangles.size());
  compute_stats(scene, e);
}

void update_element_stats(Scene& scene) {
  for (Element& e : scene.elements) compute_stats(scene, e);
}

}  // namespace ewis
