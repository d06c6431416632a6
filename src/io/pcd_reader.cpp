// PCD reader (PCL's format, v0.5 and v0.7): DATA ascii, binary (records, AoS) and binary_compressed
// (uint32 compressed size, uint32 raw size, LZF stream of field-major (SoA) arrays).
#include <lzf.h>

#include <cstring>

#include "cloud_builder.hpp"
#include "ewis/core/error.hpp"
#include "ewis/core/scratch.hpp"
#include "pcd_header.hpp"
#include "readers.hpp"
#include "text_scan.hpp"

namespace ewis::io_detail {

namespace {

// Decodes every kept field; field f starts at base + field_offset[f], records `stride[f]` bytes apart.
void decode_fields(const PcdHeader& h, const char* base, const std::vector<std::size_t>& field_offset,
                   const std::vector<std::size_t>& stride, CloudBuilder& out) {
  const bool swap = !host_is_little_endian();  // PCL writes host (little-endian) order
  for (std::size_t f = 0; f < h.fields.size(); ++f) {
    if (std::uint32_t* packed = out.packed_dest(f)) {
      decode_column_u32(base + field_offset[f], stride[f], h.points, swap, packed);
      continue;
    }
    std::size_t ds;
    if (float* dst = out.float_dest(f, ds))
      decode_column(base + field_offset[f], stride[f], h.points, h.fields[f].type, swap, dst, ds);
  }
}

void read_binary(const std::string& path, std::string_view bytes, const PcdHeader& h, CloudBuilder& out) {
  std::vector<std::size_t> off, stride(h.fields.size(), h.point_bytes);
  std::size_t o = 0;
  for (const auto& f : h.fields) off.push_back(o), o += scalar_size(f.type) * f.count;
  decode_fields(h, bytes.data() + h.body_offset, off, stride, out);
}

// Decompresses the whole body (checked sizes, exact LZF length) before anything is allocated per point.
ScratchArray<char> decompress(const std::string& path, std::string_view bytes, const PcdHeader& h) {
  const std::size_t left = bytes.size() - h.body_offset;
  if (left < 8) throw InputError(path, "truncated: binary_compressed data has no size fields");
  const char* p = bytes.data() + h.body_offset;
  const std::uint32_t comp = load<std::uint32_t>(p, !host_is_little_endian());
  const std::uint32_t raw = load<std::uint32_t>(p + 4, !host_is_little_endian());
  if (comp > left - 8)
    throw InputError(path, "truncated: compressed size " + std::to_string(comp) + " but only " +
                               std::to_string(left - 8) + " bytes follow");
  if (raw != std::uint64_t(h.points) * h.point_bytes)
    throw InputError(path, "binary_compressed: uncompressed size " + std::to_string(raw) + " does not match " +
                               std::to_string(h.points) + " points x " + std::to_string(h.point_bytes) + " bytes");
  if (raw == 0) return {};
  // LZF expands at most ~88x (a 3-byte back-reference covers 264 bytes): a larger claim is a lie; refuse it
  // before allocating.
  if (std::uint64_t(raw) > std::uint64_t(comp) * 100 + 64)
    throw InputError(path, "binary_compressed: uncompressed size " + std::to_string(raw) +
                               " is impossible for " + std::to_string(comp) + " compressed bytes");
  ScratchArray<char> buf(raw);  // huge pages: its first touch is the decompression (core/scratch.hpp)
  const unsigned got = lzf_decompress(p + 8, comp, buf.data(), raw);
  if (got != raw) throw InputError(path, "binary_compressed: the LZF data does not decompress");
  return buf;
}

void decode_soa(const char* raw, const PcdHeader& h, CloudBuilder& out) {
  if (!raw) return;
  std::vector<std::size_t> off, stride;
  std::size_t o = 0;
  for (const auto& f : h.fields) {
    const std::size_t s = scalar_size(f.type) * f.count;
    off.push_back(o), stride.push_back(s);
    o += s * h.points;
  }
  decode_fields(h, raw, off, stride, out);
}

void read_ascii(const std::string& path, std::string_view bytes, const PcdHeader& h, CloudBuilder& out) {
  TokenCursor cur(bytes.data() + h.body_offset, bytes.data() + bytes.size(), h.body_line);
  const std::size_t nf = h.fields.size();
  std::vector<float*> dst(nf);
  std::vector<std::size_t> ds(nf, 1);
  for (std::size_t f = 0; f < nf; ++f) dst[f] = out.float_dest(f, ds[f]);
  std::string_view tok;
  for (std::size_t i = 0; i < h.points; ++i) {
    for (std::size_t f = 0; f < nf; ++f) {
      const FieldSpec& fs = h.fields[f];
      for (std::size_t k = 0; k < fs.count; ++k) {
        if (!cur.next(tok))
          throw InputError(path, "truncated: the data ends at point " + std::to_string(i) + " of " +
                                     std::to_string(h.points));
        if (fs.count != 1) continue;  // multi-value fields (histograms) are listed, not kept
        const auto bad = [&] {
          return InputError(path, "line " + std::to_string(cur.line) + ": cannot read '" + excerpt(tok) +
                                      "' as a number (field '" + fs.name + "')");
        };
        if (std::uint32_t* packed = out.packed_dest(f)) {
          if (fs.type == ScalarType::Float32) {
            float v;  // PCL's rgb: a float whose bits are 0xAARRGGBB
            if (!parse_number(tok, v)) throw bad();
            std::memcpy(&packed[i], &v, 4);
          } else {
            std::uint64_t v = 0;  // set by parse_number (zeroed: g++ 12 with the sanitizers' flags cannot tell)
            if (!parse_number(tok, v)) throw bad();
            packed[i] = static_cast<std::uint32_t>(v);
          }
        } else if (fs.type == ScalarType::Float32) {
          float v;
          if (!parse_number(tok, v)) throw bad();
          if (dst[f]) dst[f][i * ds[f]] = v;
        } else {
          double v;
          if (!parse_number(tok, v)) throw bad();
          if (dst[f]) dst[f][i * ds[f]] = narrow_to_float(v);
        }
      }
    }
  }
}

}  // namespace

CloudFile read_pcd(const std::string& path, std::string_view bytes, float to_mm) {
  const PcdHeader h = parse_pcd_header(path, bytes);
  {
    const auto roles = assign_roles(h.fields);
    int xyz = 0;
    for (auto r : roles) xyz += (r == Role::X) + (r == Role::Y) + (r == Role::Z);
    if (xyz != 3) throw InputError(path, "PCD file has no x, y and z fields");
  }
  // The header may lie about the count: check it against the bytes left BEFORE allocating anything.
  const std::size_t left = bytes.size() - h.body_offset;
  const std::string lie =
      "header declares " + std::to_string(h.points) + " points but the file is too short for them";
  if (h.data == PcdData::Binary) {
    if (h.point_bytes == 0 || h.points > left / h.point_bytes) {
      if (h.points != 0) throw InputError(path, lie);
    }
  } else if (h.data == PcdData::Ascii) {
    std::size_t values = 0;
    for (const auto& f : h.fields) values += f.count;
    if (h.points > (left + 1) / 2 / values) throw InputError(path, lie);
  }
  // binary_compressed: the sizes are checked and the stream decompressed (to exactly points x point_bytes)
  // before the cloud is allocated.
  ScratchArray<char> raw;
  if (h.data == PcdData::BinaryCompressed) raw = decompress(path, bytes, h);
  CloudBuilder builder(h.fields, h.points);
  if (h.data == PcdData::Binary) read_binary(path, bytes, h, builder);
  else if (h.data == PcdData::BinaryCompressed) decode_soa(raw.data(), h, builder);
  else read_ascii(path, bytes, h, builder);

  std::vector<std::string> names;
  for (const auto& f : h.fields)
    if (f.name != "_") names.push_back(f.name);
  return builder.finish(std::move(names), h.width, h.height, to_mm);
}

}  // namespace ewis::io_detail
