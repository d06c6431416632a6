#include "scalar_type.hpp"

#include <limits>
#include <type_traits>

namespace ewis::io_detail {

bool parse_ply_type(std::string_view n, ScalarType& out) {
  if (n == "char" || n == "int8") out = ScalarType::Int8;
  else if (n == "uchar" || n == "uint8") out = ScalarType::UInt8;
  else if (n == "short" || n == "int16") out = ScalarType::Int16;
  else if (n == "ushort" || n == "uint16") out = ScalarType::UInt16;
  else if (n == "int" || n == "int32") out = ScalarType::Int32;
  else if (n == "uint" || n == "uint32") out = ScalarType::UInt32;
  else if (n == "float" || n == "float32") out = ScalarType::Float32;
  else if (n == "double" || n == "float64") out = ScalarType::Float64;
  else return false;
  return true;
}

bool parse_pcd_type(char letter, std::size_t size, ScalarType& out) {
  switch (letter) {
    case 'F':
      if (size == 4) out = ScalarType::Float32;
      else if (size == 8) out = ScalarType::Float64;
      else return false;
      return true;
    case 'I':
      if (size == 1) out = ScalarType::Int8;
      else if (size == 2) out = ScalarType::Int16;
      else if (size == 4) out = ScalarType::Int32;
      else if (size == 8) out = ScalarType::Int64;
      else return false;
      return true;
    case 'U':
      if (size == 1) out = ScalarType::UInt8;
      else if (size == 2) out = ScalarType::UInt16;
      else if (size == 4) out = ScalarType::UInt32;
      else if (size == 8) out = ScalarType::UInt64;
      else return false;
      return true;
    default: return false;
  }
}

namespace {
template <class T>
inline float to_float(T v) {
  if constexpr (std::is_same_v<T, double>) return narrow_to_float(v);
  else return static_cast<float>(v);
}

template <class T>
void decode_typed(const char* src, std::size_t stride, std::size_t n, bool swap, float* dst, std::size_t dst_stride) {
  // The loop is specialised per type and per swap so it compiles to plain loads (no dispatch per point).
  if (swap) {
    for (std::size_t i = 0; i < n; ++i) dst[i * dst_stride] = to_float(load<T>(src + i * stride, true));
  } else {
    for (std::size_t i = 0; i < n; ++i) dst[i * dst_stride] = to_float(load<T>(src + i * stride, false));
  }
}
}  // namespace

void decode_column(const char* src, std::size_t stride, std::size_t n, ScalarType t, bool swap, float* dst,
                   std::size_t dst_stride) {
  switch (t) {
    case ScalarType::Int8: return decode_typed<std::int8_t>(src, stride, n, swap, dst, dst_stride);
    case ScalarType::UInt8: return decode_typed<std::uint8_t>(src, stride, n, swap, dst, dst_stride);
    case ScalarType::Int16: return decode_typed<std::int16_t>(src, stride, n, swap, dst, dst_stride);
    case ScalarType::UInt16: return decode_typed<std::uint16_t>(src, stride, n, swap, dst, dst_stride);
    case ScalarType::Int32: return decode_typed<std::int32_t>(src, stride, n, swap, dst, dst_stride);
    case ScalarType::UInt32: return decode_typed<std::uint32_t>(src, stride, n, swap, dst, dst_stride);
    case ScalarType::Int64: return decode_typed<std::int64_t>(src, stride, n, swap, dst, dst_stride);
    case ScalarType::UInt64: return decode_typed<std::uint64_t>(src, stride, n, swap, dst, dst_stride);
    case ScalarType::Float32: return decode_typed<float>(src, stride, n, swap, dst, dst_stride);
    case ScalarType::Float64: return decode_typed<double>(src, stride, n, swap, dst, dst_stride);
  }
}

void decode_column_u32(const char* src, std::size_t stride, std::size_t n, bool swap, std::uint32_t* dst) {
  for (std::size_t i = 0; i < n; ++i) dst[i] = load<std::uint32_t>(src + i * stride, swap);
}

}  // namespace ewis::io_detail
