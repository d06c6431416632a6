#pragma once
// Internal to io/: the PLY header (http://paulbourke.net/dataformats/ply/): format, elements, properties.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "scalar_type.hpp"

namespace ewis::io_detail {

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyProperty {
  std::string name;
  ScalarType type = ScalarType::Float32;  // the item type for a list
  bool is_list = false;
  ScalarType count_type = ScalarType::UInt8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  bool has_lists() const {
    for (const auto& p : properties)
      if (p.is_list) return true;
    return false;
  }
  // Bytes of one record without lists (lists count their length field only): a lower bound otherwise.
  std::size_t min_record_bytes() const {
    std::size_t s = 0;
    for (const auto& p : properties) s += scalar_size(p.is_list ? p.count_type : p.type);
    return s;
  }
};

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;  // first byte after the end_header line
  std::size_t body_line = 1;    // line number of the first body line (for ascii error messages)
};

// Throws InputError(path, ...) on a malformed header or an unknown property type.
PlyHeader parse_ply_header(const std::string& path, std::string_view bytes);

}  // namespace ewis::io_detail
