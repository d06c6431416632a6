// PLY reader: ascii, binary_little_endian, binary_big_endian. The vertex element is decoded column by column
// straight into the Cloud (no per-point dispatch); elements before it (faces, range grids) are skipped with
// every length checked against the bytes that are left.
#include <cmath>
#include <cstring>

#include "cloud_builder.hpp"
#include "ewis/core/error.hpp"
#include "ply_header.hpp"
#include "readers.hpp"
#include "text_scan.hpp"

namespace ewis::io_detail {

namespace {

std::string count_str(std::uint64_t n) { return std::to_string(n); }

// A list length read from the file: a non-negative integer, else the file is corrupt.
std::uint64_t list_length(const std::string& path, double v, const std::string& element) {
  if (!(v >= 0) || v != std::floor(v) || v > 4294967295.0)
    throw InputError(path, "bad list length in element '" + element + "'");
  return static_cast<std::uint64_t>(v);
}

// ---- binary ----

// Skips a whole element; returns the offset after it.
std::size_t skip_binary_element(const std::string& path, std::string_view b, std::size_t pos, const PlyElement& e,
                                bool swap) {
  if (e.properties.empty() || e.count == 0) return pos;
  const std::string truncated = "truncated in element '" + e.name + "' (" + count_str(e.count) + " records)";
  if (!e.has_lists()) {
    const std::size_t rec = e.min_record_bytes();
    if (e.count > (b.size() - pos) / rec) throw InputError(path, truncated);
    return pos + static_cast<std::size_t>(e.count) * rec;
  }
  // Each record takes at least one byte, so a lying count runs out of bytes long before it runs long.
  if (e.count > (b.size() - pos) / e.min_record_bytes()) throw InputError(path, truncated);
  for (std::uint64_t r = 0; r < e.count; ++r) {
    for (const auto& p : e.properties) {
      if (!p.is_list) {
        const std::size_t s = scalar_size(p.type);
        if (b.size() - pos < s) throw InputError(path, truncated);
        pos += s;
        continue;
      }
      const std::size_t cs = scalar_size(p.count_type);
      if (b.size() - pos < cs) throw InputError(path, truncated);
      const std::uint64_t n = list_length(path, load_as_double(b.data() + pos, p.count_type, swap), e.name);
      pos += cs;
      const std::size_t is = scalar_size(p.type);
      if (n > (b.size() - pos) / is) throw InputError(path, truncated);
      pos += static_cast<std::size_t>(n) * is;
    }
  }
  return pos;
}

void decode_binary_vertices(const std::string& path, std::string_view b, std::size_t pos, const PlyElement& e,
                            bool swap, CloudBuilder& out) {
  const std::size_t n = out.size();
  if (n == 0) return;
  if (!e.has_lists()) {
    // Fixed stride: the count was checked against the bytes left before allocating.
    const std::size_t stride = e.min_record_bytes();
    std::size_t off = 0;
    std::vector<std::size_t> offsets;
    for (const auto& p : e.properties) offsets.push_back(off), off += scalar_size(p.type);
    const char* base = b.data() + pos;
    // Fast path: a float32 triple (x y z, nx ny nz) next to each other in host order goes to its Vector3f with
    // one 12-byte copy per record (one block copy when that is the whole record).
    const auto triple_at = [&](std::size_t f) {
      if (swap || f + 2 >= e.properties.size()) return false;
      const Role r = out.role(f);
      const bool is_pos = r == Role::X && out.role(f + 1) == Role::Y && out.role(f + 2) == Role::Z;
      const bool nrm = r == Role::NX && out.role(f + 1) == Role::NY && out.role(f + 2) == Role::NZ;
      return (is_pos || nrm) && e.properties[f].type == ScalarType::Float32 &&
             e.properties[f + 1].type == ScalarType::Float32 && e.properties[f + 2].type == ScalarType::Float32;
    };
    for (std::size_t f = 0; f < e.properties.size(); ++f) {
      if (triple_at(f)) {
        std::size_t ds;
        float* dst = out.float_dest(f, ds);
        const char* src = base + offsets[f];
        if (stride == 12) std::memcpy(dst, src, n * 12);
        else
          for (std::size_t i = 0; i < n; ++i) std::memcpy(dst + 3 * i, src + i * stride, 12);
        f += 2;
        continue;
      }
      if (std::uint32_t* packed = out.packed_dest(f)) {
        decode_column_u32(base + offsets[f], stride, n, swap, packed);
        continue;
      }
      std::size_t ds;
      if (float* dst = out.float_dest(f, ds))
        decode_column(base + offsets[f], stride, n, e.properties[f].type, swap, dst, ds);
    }
    return;
  }
  // Records with list properties (rare for vertices): walk them one by one, every read bounds-checked.
  const std::string truncated = "truncated in element 'vertex' (" + count_str(e.count) + " vertices)";
  std::vector<float*> dst(e.properties.size());
  std::vector<std::size_t> ds(e.properties.size());
  for (std::size_t f = 0; f < e.properties.size(); ++f) dst[f] = e.properties[f].is_list ? nullptr : out.float_dest(f, ds[f]);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t f = 0; f < e.properties.size(); ++f) {
      const auto& p = e.properties[f];
      if (!p.is_list) {
        const std::size_t s = scalar_size(p.type);
        if (b.size() - pos < s) throw InputError(path, truncated);
        if (std::uint32_t* packed = out.packed_dest(f)) packed[i] = load<std::uint32_t>(b.data() + pos, swap);
        else if (dst[f]) dst[f][i * ds[f]] = narrow_to_float(load_as_double(b.data() + pos, p.type, swap));
        pos += s;
        continue;
      }
      const std::size_t cs = scalar_size(p.count_type);
      if (b.size() - pos < cs) throw InputError(path, truncated);
      const std::uint64_t len = list_length(path, load_as_double(b.data() + pos, p.count_type, swap), e.name);
      pos += cs;
      const std::size_t is = scalar_size(p.type);
      if (len > (b.size() - pos) / is) throw InputError(path, truncated);
      pos += static_cast<std::size_t>(len) * is;
    }
  }
}

// ---- ascii ----

std::string_view need_token(const std::string& path, TokenCursor& cur, const PlyElement& e) {
  std::string_view tok;
  if (!cur.next(tok))
    throw InputError(path, "truncated: the file ends inside element '" + e.name + "' (" + count_str(e.count) +
                               " records declared)");
  return tok;
}

std::uint64_t ascii_list_length(const std::string& path, TokenCursor& cur, const PlyElement& e) {
  const std::string_view tok = need_token(path, cur, e);
  std::uint64_t n = 0;
  if (!parse_number(tok, n))
    throw InputError(path, "line " + std::to_string(cur.line) + ": bad list length '" + excerpt(tok) + "'");
  return n;
}

void skip_ascii_element(const std::string& path, TokenCursor& cur, const PlyElement& e) {
  if (e.properties.empty()) return;
  // Every record takes at least one token, so the loop ends when the tokens do, whatever the count says.
  for (std::uint64_t r = 0; r < e.count; ++r)
    for (const auto& p : e.properties) {
      if (!p.is_list) {
        need_token(path, cur, e);
        continue;
      }
      const std::uint64_t n = ascii_list_length(path, cur, e);
      for (std::uint64_t k = 0; k < n; ++k) need_token(path, cur, e);
    }
}

void decode_ascii_vertices(const std::string& path, TokenCursor& cur, const PlyElement& e, CloudBuilder& out) {
  const std::size_t nf = e.properties.size();
  std::vector<float*> dst(nf);
  std::vector<std::size_t> ds(nf, 1);
  for (std::size_t f = 0; f < nf; ++f) dst[f] = e.properties[f].is_list ? nullptr : out.float_dest(f, ds[f]);
  for (std::size_t i = 0; i < out.size(); ++i) {
    for (std::size_t f = 0; f < nf; ++f) {
      const auto& p = e.properties[f];
      if (p.is_list) {
        const std::uint64_t n = ascii_list_length(path, cur, e);
        for (std::uint64_t k = 0; k < n; ++k) need_token(path, cur, e);
        continue;
      }
      const std::string_view tok = need_token(path, cur, e);
      const auto bad = [&] {
        return InputError(path, "line " + std::to_string(cur.line) + ": cannot read '" + excerpt(tok) +
                                    "' as a number (property '" + p.name + "')");
      };
      if (std::uint32_t* packed = out.packed_dest(f)) {
        if (p.type == ScalarType::Float32) {
          float v;
          if (!parse_number(tok, v)) throw bad();
          std::memcpy(&packed[i], &v, 4);
        } else {
          double v;
          if (!parse_number(tok, v)) throw bad();
          packed[i] = (v >= 0 && v <= 4294967295.0) ? static_cast<std::uint32_t>(v) : 0u;
        }
      } else if (p.type == ScalarType::Float32) {
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

}  // namespace

CloudFile read_ply(const std::string& path, std::string_view bytes, float to_mm) {
  const PlyHeader h = parse_ply_header(path, bytes);
  std::size_t vi = h.elements.size();
  for (std::size_t i = 0; i < h.elements.size(); ++i)
    if (h.elements[i].name == "vertex") {
      vi = i;
      break;
    }
  if (vi == h.elements.size()) throw InputError(path, "PLY file has no 'vertex' element");
  const PlyElement& v = h.elements[vi];
  std::vector<FieldSpec> specs;
  std::vector<std::string> names;
  for (const auto& p : v.properties) {
    specs.push_back({p.name, p.type, p.is_list ? std::size_t(0) : std::size_t(1)});
    names.push_back(p.name);
  }
  {
    const auto roles = assign_roles(specs);
    int xyz = 0;
    for (auto r : roles) xyz += (r == Role::X) + (r == Role::Y) + (r == Role::Z);
    if (xyz != 3) throw InputError(path, "PLY vertex element has no x, y and z properties");
  }

  const bool binary = h.format != PlyFormat::Ascii;
  const bool swap = binary && ((h.format == PlyFormat::BinaryLittleEndian) != host_is_little_endian());
  std::size_t pos = h.body_offset;
  TokenCursor cur(bytes.data() + pos, bytes.data() + bytes.size(), h.body_line);
  for (std::size_t i = 0; i < vi; ++i) {
    if (binary) pos = skip_binary_element(path, bytes, pos, h.elements[i], swap);
    else skip_ascii_element(path, cur, h.elements[i]);
  }

  // The header may lie about the count: check it against the bytes left BEFORE allocating anything.
  const std::size_t left = binary ? bytes.size() - pos : static_cast<std::size_t>(cur.end - cur.p);
  const std::string lie = "header declares " + count_str(v.count) + " vertices but the file is too short for them";
  if (binary) {
    if (v.count > left / v.min_record_bytes()) throw InputError(path, lie);
  } else {
    // Each ascii value takes at least one character and one separator.
    if (v.count > (left + 1) / 2 / std::max<std::size_t>(v.properties.size(), 1)) throw InputError(path, lie);
  }
  CloudBuilder builder(specs, static_cast<std::size_t>(v.count));
  if (binary) decode_binary_vertices(path, bytes, pos, v, swap, builder);
  else decode_ascii_vertices(path, cur, v, builder);
  return builder.finish(std::move(names), static_cast<std::size_t>(v.count), 1, to_mm);
}

}  // namespace ewis::io_detail
