#pragma once
// Shared by the fuzz targets: invariants every parser result must satisfy, and a per-process temp file for the
// entry points that take a path. A broken invariant aborts (libFuzzer records the input as a crash).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "ewis/core/error.hpp"
#include "ewis/io/cloud_io.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis_fuzz {

[[noreturn]] inline void broken(const char* what) {
  std::fprintf(stderr, "fuzz invariant broken: %s\n", what);
  std::abort();
}

// A reader's result: finite points, attribute vectors empty or as long as the points.
inline void check_cloud(const ewis::CloudFile& f) {
  const ewis::Cloud& c = f.cloud;
  const std::size_t n = c.points.size();
  for (const auto& p : c.points)
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z())) broken("non-finite point kept");
  if (!c.normals.empty() && c.normals.size() != n) broken("normals size");
  if (!c.colors.empty() && c.colors.size() != n) broken("colors size");
  if (!c.intensities.empty() && c.intensities.size() != n) broken("intensities size");
  for (const auto& s : c.scalars)
    if (s.values.size() != n) broken("scalar field size");
  if (f.fields.size() > 100000) broken("absurd field count");
}

// A loaded scene: triangle indices in range, elements contiguous and covering every triangle.
inline void check_scene(const ewis::Scene& s) {
  if (s.triangle_element.size() != s.triangles.size()) broken("triangle_element size");
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k)
      if (t[k] < 0 || std::size_t(t[k]) >= s.vertices.size()) broken("triangle index out of range");
  std::size_t covered = 0;
  for (std::size_t e = 0; e < s.elements.size(); ++e) {
    const auto& el = s.elements[e];
    if (std::size_t(el.first_triangle) + el.triangle_count > s.triangles.size()) broken("element range");
    for (std::uint32_t i = 0; i < el.triangle_count; ++i)
      if (s.triangle_element[el.first_triangle + i] != e) broken("element not contiguous");
    covered += el.triangle_count;
  }
  if (covered != s.triangles.size()) broken("elements do not cover the triangles");
  if (s.triangles.empty()) broken("load_scene returned an empty scene instead of throwing");
}

// /dev/shm/ewis-fuzz-<pid>.<ext> (RAM-backed), rewritten each run, removed at exit.
class TempFile {
 public:
  explicit TempFile(const std::string& ext) {
    const char* dir = std::getenv("EWIS_FUZZ_TMP");
    path_ = std::string(dir ? dir : "/dev/shm") + "/ewis-fuzz-" + std::to_string(::getpid()) + "." + ext;
  }
  ~TempFile() { std::remove(path_.c_str()); }
  const std::string& write(const uint8_t* data, size_t size) {
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (!f) broken("cannot write the temporary file");
    if (size && std::fwrite(data, 1, size, f) != size) broken("short write of the temporary file");
    std::fclose(f);
    return path_;
  }

 private:
  std::string path_;
};

}  // namespace ewis_fuzz
