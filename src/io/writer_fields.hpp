#pragma once
// Internal to io/: the per-point fields the writers store, in order, and their validation.
#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "ewis/core/cloud.hpp"

namespace ewis::io_detail {

// Throws std::invalid_argument when an attribute vector is neither empty nor as long as the points.
void check_cloud_attributes(const Cloud& cloud);

// A scalar field's name as a single header word ("my field" -> "my_field", "" -> "scalar<k>").
std::string header_word(const std::string& name, std::size_t k);

// Little-endian store of a 4-byte value (the writers' byte order).
inline void store_le32(char* dst, const void* src) {
  std::uint32_t u;
  std::memcpy(&u, src, 4);
  if constexpr (std::endian::native == std::endian::big) u = __builtin_bswap32(u);
  std::memcpy(dst, &u, 4);
}

}  // namespace ewis::io_detail
