#pragma once
// Helpers for the io tests: a temp folder, raw file writing and an independent PLY encoder (any format,
// any property type, list properties) so the reader is checked against bytes it did not write itself.
#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "ewis/core/cloud.hpp"
#include "test_tmp.hpp"

namespace io_test {

inline std::string tmp_dir() {
  return ewis::test::own_tmp_dir("io").string();
}

inline std::string write_bytes(const std::string& name, const std::string& content) {
  const std::string p = tmp_dir() + "/" + name;
  // Unlink first: truncating an existing file makes ext4 flush it on close (auto_da_alloc), which is slow.
  std::filesystem::remove(p);
  std::ofstream(p, std::ios::binary) << content;
  return p;
}

inline std::string realdata(const std::string& rel) { return std::string(EWIS_REALDATA_DIR) + "/" + rel; }

struct PlyProp {
  std::string name;
  std::string type;          // item type for a list
  std::string count_type;    // non-empty: a list property
};
struct PlyElem {
  std::string name;
  std::vector<PlyProp> props;
  // Per record, the values in property order; a list contributes its length then its items.
  std::vector<std::vector<double>> records;
};

inline std::size_t type_bytes(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "double" || t == "float64") return 8;
  return 4;
}

inline void put(std::string& out, const std::string& t, double v, bool big) {
  char b[8];
  const std::size_t n = type_bytes(t);
  if (t == "char" || t == "int8") { std::int8_t x = std::int8_t(v); std::memcpy(b, &x, 1); }
  else if (t == "uchar" || t == "uint8") { std::uint8_t x = std::uint8_t(v); std::memcpy(b, &x, 1); }
  else if (t == "short" || t == "int16") { std::int16_t x = std::int16_t(v); std::memcpy(b, &x, 2); }
  else if (t == "ushort" || t == "uint16") { std::uint16_t x = std::uint16_t(v); std::memcpy(b, &x, 2); }
  else if (t == "int" || t == "int32") { std::int32_t x = std::int32_t(v); std::memcpy(b, &x, 4); }
  else if (t == "uint" || t == "uint32") { std::uint32_t x = std::uint32_t(v); std::memcpy(b, &x, 4); }
  else if (t == "float" || t == "float32") { float x = float(v); std::memcpy(b, &x, 4); }
  else { std::memcpy(b, &v, 8); }
  if (big) std::reverse(b, b + n);  // the test host is little-endian (x86/arm64)
  out.append(b, n);
}

inline std::string fmt_num(const std::string& t, double v) {
  char buf[64];
  if (t == "float" || t == "float32") std::snprintf(buf, sizeof buf, "%.9g", v);
  else if (t == "double" || t == "float64") std::snprintf(buf, sizeof buf, "%.17g", v);
  else std::snprintf(buf, sizeof buf, "%lld", (long long)v);
  return buf;
}

// format: "ascii", "binary_little_endian" or "binary_big_endian".
inline std::string encode_ply(const std::string& format, const std::vector<PlyElem>& elems) {
  std::string out = "ply\nformat " + format + " 1.0\ncomment made by io_test\n";
  for (const auto& e : elems) {
    out += "element " + e.name + " " + std::to_string(e.records.size()) + "\n";
    for (const auto& p : e.props)
      out += p.count_type.empty() ? "property " + p.type + " " + p.name + "\n"
                                  : "property list " + p.count_type + " " + p.type + " " + p.name + "\n";
  }
  out += "end_header\n";
  const bool ascii = format == "ascii", big = format == "binary_big_endian";
  for (const auto& e : elems)
    for (const auto& r : e.records) {
      std::size_t k = 0;
      std::string line;
      for (const auto& p : e.props) {
        if (p.count_type.empty()) {
          if (ascii) line += fmt_num(p.type, r.at(k)) + " ";
          else put(out, p.type, r.at(k), big);
          ++k;
        } else {
          const std::size_t n = std::size_t(r.at(k));
          if (ascii) line += fmt_num(p.count_type, r.at(k)) + " ";
          else put(out, p.count_type, r.at(k), big);
          ++k;
          for (std::size_t j = 0; j < n; ++j, ++k) {
            if (ascii) line += fmt_num(p.type, r.at(k)) + " ";
            else put(out, p.type, r.at(k), big);
          }
        }
      }
      if (ascii) out += line + "\n";
    }
  return out;
}

// A small cloud with every attribute, values chosen to be exact in float.
inline ewis::Cloud sample_cloud(std::size_t n, bool attributes = true) {
  ewis::Cloud c;
  for (std::size_t i = 0; i < n; ++i) {
    const float t = float(i);
    c.points.emplace_back(t * 0.5f - 3.25f, 100.0f + t, -t * 0.125f);
    if (!attributes) continue;
    c.normals.emplace_back(Eigen::Vector3f(1.0f, t, 2.0f).normalized());
    c.colors.push_back({std::uint8_t(i % 256), std::uint8_t((3 * i) % 256), std::uint8_t(255 - i % 256)});
    c.intensities.push_back(0.25f * t);
  }
  if (attributes) {
    c.scalars.push_back({"curvature", {}});
    for (std::size_t i = 0; i < n; ++i) c.scalars[0].values.push_back(float(i) / 7.0f);
  }
  return c;
}

}  // namespace io_test
