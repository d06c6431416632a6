// Wavefront OBJ writer: one `o NAME` per element, written atomically.
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <system_error>

#include "ewis/core/error.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis {
namespace {

void append_float(std::string& out, float x) {
  char buf[32];
  // Shortest representation that reads back to the same float: the round trip keeps every vertex exactly.
  const auto r = std::to_chars(buf, buf + sizeof(buf), x);
  out.append(buf, r.ptr);
}

void append_int(std::string& out, long long x) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof(buf), x);
  out.append(buf, r.ptr);
}

// Assimp's OBJ reader ends an object name at the first blank, so blanks become '_' (else "a b" would
// read back as "a" and merge with another element).
std::string one_line(const std::string& name) {
  std::string s = name;
  for (char& c : s)
    if (c == '\n' || c == '\r' || c == ' ' || c == '\t') c = '_';
  return s.empty() ? std::string("unnamed") : s;
}

}  // namespace

void write_obj(const Scene& scene, const std::string& path) {
  namespace fs = std::filesystem;
  std::string text;
  text.reserve(scene.vertices.size() * 36 + scene.triangles.size() * 24 + 64);
  text += "# ewis-inspect scene: ";
  append_int(text, static_cast<long long>(scene.elements.size()));
  text += " elements\n";
  for (const Eigen::Vector3f& v : scene.vertices) {
    text += "v ";
    append_float(text, v.x());
    text += ' ';
    append_float(text, v.y());
    text += ' ';
    append_float(text, v.z());
    text += '\n';
  }
  for (const Element& e : scene.elements) {
    text += "o ";
    text += one_line(e.name);
    text += '\n';
    const std::size_t end = std::size_t(e.first_triangle) + e.triangle_count;
    for (std::size_t t = e.first_triangle; t < end && t < scene.triangles.size(); ++t) {
      const Eigen::Vector3i& tri = scene.triangles[t];
      text += 'f';
      for (int k = 0; k < 3; ++k) {
        text += ' ';
        append_int(text, static_cast<long long>(tri[k]) + 1);  // OBJ indices are 1-based
      }
      text += '\n';
    }
  }

  // Atomic: a reader never sees a half-written file (temporary in the same folder, then rename).
  const fs::path target(path);
  std::random_device rd;
  const fs::path tmp = target.parent_path() / (target.filename().string() + ".tmp" + std::to_string(rd()));
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path, "cannot open for writing");
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.flush();
    if (!out) {
      out.close();
      std::error_code ec;
      fs::remove(tmp, ec);
      throw InputError(path, "write failed");
    }
  }
  if (std::rename(tmp.c_str(), target.c_str()) != 0) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw InputError(path, "cannot replace file");
  }
}

}  // namespace ewis
