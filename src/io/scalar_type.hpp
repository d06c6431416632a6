#pragma once
// Internal to io/: the binary scalar types of PLY and PCD, and column decoding without per-point dispatch.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

namespace ewis::io_detail {

enum class ScalarType : std::uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };

inline std::size_t scalar_size(ScalarType t) {
  switch (t) {
    case ScalarType::Int8: case ScalarType::UInt8: return 1;
    case ScalarType::Int16: case ScalarType::UInt16: return 2;
    case ScalarType::Int32: case ScalarType::UInt32: case ScalarType::Float32: return 4;
    default: return 8;
  }
}
inline bool is_float(ScalarType t) { return t == ScalarType::Float32 || t == ScalarType::Float64; }

// PLY type names and their sized aliases; false for anything else.
bool parse_ply_type(std::string_view name, ScalarType& out);
// PCD TYPE letter (F, I, U) with SIZE in bytes; false for an unsupported combination.
bool parse_pcd_type(char letter, std::size_t size, ScalarType& out);

template <class T>
inline T load(const char* p, bool swap) {
  if constexpr (sizeof(T) == 1) {
    T v;
    std::memcpy(&v, p, 1);
    return v;
  } else {
    using U = std::conditional_t<sizeof(T) == 2, std::uint16_t,
                                 std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>;
    U u;
    std::memcpy(&u, p, sizeof(U));
    if (swap) {
      if constexpr (sizeof(T) == 2) u = __builtin_bswap16(u);
      else if constexpr (sizeof(T) == 4) u = __builtin_bswap32(u);
      else u = __builtin_bswap64(u);
    }
    return std::bit_cast<T>(u);
  }
}

// double -> float out of float's range is undefined behaviour in C++: make it +-inf (then dropped as non-finite).
inline float narrow_to_float(double v) {
  if (v > 3.4028234663852886e38) return __builtin_huge_valf();
  if (v < -3.4028234663852886e38) return -__builtin_huge_valf();
  return static_cast<float>(v);
}

// One value of type t at p, as double (for per-record walks over list-bearing elements).
inline double load_as_double(const char* p, ScalarType t, bool swap) {
  switch (t) {
    case ScalarType::Int8: return load<std::int8_t>(p, swap);
    case ScalarType::UInt8: return load<std::uint8_t>(p, swap);
    case ScalarType::Int16: return load<std::int16_t>(p, swap);
    case ScalarType::UInt16: return load<std::uint16_t>(p, swap);
    case ScalarType::Int32: return load<std::int32_t>(p, swap);
    case ScalarType::UInt32: return load<std::uint32_t>(p, swap);
    case ScalarType::Int64: return double(load<std::int64_t>(p, swap));
    case ScalarType::UInt64: return double(load<std::uint64_t>(p, swap));
    case ScalarType::Float32: return load<float>(p, swap);
    default: return load<double>(p, swap);
  }
}

// dst[i * dst_stride] = float(value of record i), records `stride` bytes apart starting at `src`.
// The caller has checked that src + (n-1)*stride + size(t) lies inside the buffer.
void decode_column(const char* src, std::size_t stride, std::size_t n, ScalarType t, bool swap, float* dst,
                   std::size_t dst_stride);
// The raw 4 bytes of each record as uint32 (packed PCD rgb/rgba, whatever its declared F or U type).
void decode_column_u32(const char* src, std::size_t stride, std::size_t n, bool swap, std::uint32_t* dst);

inline bool host_is_little_endian() { return std::endian::native == std::endian::little; }

}  // namespace ewis::io_detail
