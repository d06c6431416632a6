#pragma once
// Internal to io/: the PCD header (PCL's format, v0.5 and v0.7).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "cloud_builder.hpp"

namespace ewis::io_detail {

enum class PcdData { Ascii, Binary, BinaryCompressed };

struct PcdHeader {
  std::vector<FieldSpec> fields;  // with their SIZE (from the type), TYPE and COUNT
  std::size_t width = 0, height = 1;
  std::size_t points = 0;
  std::size_t point_bytes = 0;  // sum of size * count over the fields
  PcdData data = PcdData::Ascii;
  std::size_t body_offset = 0;  // first byte after the DATA line
  std::size_t body_line = 1;
};

// Throws InputError(path, ...) on a malformed or self-contradicting header.
PcdHeader parse_pcd_header(const std::string& path, std::string_view bytes);

}  // namespace ewis::io_detail
