// Strict PLY mesh reader (ascii, binary little/big endian): vertices x, y, z and face vertex lists.
#include "read_ply_mesh.hpp"

#include <bit>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <sstream>

#include "ewis/core/error.hpp"

namespace ewis::detail {
namespace {

enum class Type { i8, u8, i16, u16, i32, u32, f32, f64, none };

Type parse_type(const std::string& s) {
  if (s == "char" || s == "int8") return Type::i8;
  if (s == "uchar" || s == "uint8") return Type::u8;
  if (s == "short" || s == "int16") return Type::i16;
  if (s == "ushort" || s == "uint16") return Type::u16;
  if (s == "int" || s == "int32") return Type::i32;
  if (s == "uint" || s == "uint32") return Type::u32;
  if (s == "float" || s == "float32") return Type::f32;
  if (s == "double" || s == "float64") return Type::f64;
  return Type::none;
}

int type_size(Type t) {
  switch (t) {
    case Type::i8: case Type::u8: return 1;
    case Type::i16: case Type::u16: return 2;
    case Type::i32: case Type::u32: case Type::f32: return 4;
    case Type::f64: return 8;
    default: return 0;
  }
}

struct Property {
  std::string name;
  Type type = Type::none;
  bool is_list = false;
  Type count_type = Type::none;
};

struct ElementDecl {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> props;
};

enum class Format { ascii, little, big };

// Sequential reader over the body; throws on running out of data.
class Body {
 public:
  Body(const std::string& path, const char* p, const char* end, Format f) : path_(path), p_(p), end_(end), f_(f) {}

  double read(Type t) {
    if (f_ == Format::ascii) return read_ascii();
    const int n = type_size(t);
    if (end_ - p_ < n) throw InputError(path_, "PLY data ends early (truncated file)");
    unsigned char b[8];
    std::memcpy(b, p_, n);
    p_ += n;
    const bool swap = (f_ == Format::big) == (std::endian::native == std::endian::little);
    if (swap)
      for (int i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    switch (t) {
      case Type::i8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
      case Type::u8: return b[0];
      case Type::i16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
      case Type::u16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
      case Type::i32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
      case Type::u32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
      case Type::f32: { float v; std::memcpy(&v, b, 4); return v; }
      case Type::f64: { double v; std::memcpy(&v, b, 8); return v; }
      default: throw InputError(path_, "PLY property of unknown type");
    }
  }
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }

 private:
  double read_ascii() {
    while (p_ < end_ && std::isspace(static_cast<unsigned char>(*p_))) ++p_;
    if (p_ >= end_) throw InputError(path_, "PLY data ends early (truncated file)");
    double v = 0;
    const auto r = std::from_chars(p_, end_, v);
    if (r.ec != std::errc()) throw InputError(path_, "PLY ascii data: not a number");
    p_ = r.ptr;
    return v;
  }

  const std::string& path_;
  const char* p_;
  const char* end_;
  Format f_;
};

}  // namespace

PlyMesh read_ply_mesh(const std::string& path, const std::string& bytes) {
  // ---- header ----
  const std::size_t header_end = bytes.find("end_header");
  if (bytes.compare(0, 3, "ply") != 0 && bytes.compare(0, 3, "PLY") != 0) throw InputError(path, "not a PLY file (no 'ply' magic)");
  if (header_end == std::string::npos) throw InputError(path, "PLY header has no end_header (truncated file)");
  std::size_t body = bytes.find('\n', header_end);
  if (body == std::string::npos) body = bytes.size();
  else ++body;
  std::istringstream header(bytes.substr(0, header_end));
  std::string line;
  Format format = Format::ascii;
  bool have_format = false;
  std::vector<ElementDecl> elements;
  while (std::getline(header, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "format") {
      std::string f;
      ls >> f;
      if (f == "ascii") format = Format::ascii;
      else if (f == "binary_little_endian") format = Format::little;
      else if (f == "binary_big_endian") format = Format::big;
      else throw InputError(path, "unknown PLY format '" + f + "'");
      have_format = true;
    } else if (word == "element") {
      ElementDecl e;
      long long count = -1;
      ls >> e.name >> count;
      if (!ls || count < 0) throw InputError(path, "bad PLY element line: " + line);
      e.count = static_cast<std::uint64_t>(count);
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) throw InputError(path, "PLY property before any element");
      Property p;
      std::string t;
      ls >> t;
      if (t == "list") {
        std::string ct, it;
        ls >> ct >> it >> p.name;
        p.is_list = true;
        p.count_type = parse_type(ct);
        p.type = parse_type(it);
        if (p.count_type == Type::none || p.count_type == Type::f32 || p.count_type == Type::f64)
          throw InputError(path, "bad PLY list count type: " + line);
      } else {
        p.type = parse_type(t);
        ls >> p.name;
      }
      if (p.type == Type::none || p.name.empty()) throw InputError(path, "bad PLY property line: " + line);
      elements.back().props.push_back(p);
    }
  }
  if (!have_format) throw InputError(path, "PLY header has no format line");

  // ---- body ----
  Body in(path, bytes.data() + body, bytes.data() + bytes.size(), format);
  PlyMesh mesh;
  bool have_vertices = false;
  for (const ElementDecl& e : elements) {
    // Every record takes at least one byte (binary) or two characters (ascii): bound the counts by the data.
    std::size_t min_record = 0;
    for (const Property& p : e.props) min_record += type_size(p.is_list ? p.count_type : p.type);
    if (format == Format::ascii) min_record = 2 * e.props.size();
    if (min_record > 0 && e.count > in.remaining() / min_record)
      throw InputError(path, "PLY element '" + e.name + "' count exceeds the file size (truncated file)");
    if (min_record == 0 && e.count > 0) throw InputError(path, "PLY element '" + e.name + "' has no properties");
    const bool is_vertex = e.name == "vertex";
    const bool is_face = e.name == "face";
    int ix = -1, iy = -1, iz = -1, iface = -1;
    for (std::size_t k = 0; k < e.props.size(); ++k) {
      const std::string& n = e.props[k].name;
      if (is_vertex && !e.props[k].is_list) {
        if (n == "x") ix = int(k);
        if (n == "y") iy = int(k);
        if (n == "z") iz = int(k);
      }
      if (is_face && e.props[k].is_list && (n == "vertex_indices" || n == "vertex_index")) iface = int(k);
    }
    if (is_vertex) {
      if (ix < 0 || iy < 0 || iz < 0) throw InputError(path, "PLY vertex element lacks x, y or z");
      mesh.vertices.reserve(e.count);
      have_vertices = true;
    }
    std::vector<long long> poly;
    for (std::uint64_t r = 0; r < e.count; ++r) {
      Eigen::Vector3f v = Eigen::Vector3f::Zero();
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const Property& p = e.props[k];
        if (!p.is_list) {
          const double x = in.read(p.type);
          if (int(k) == ix) v.x() = float(x);
          if (int(k) == iy) v.y() = float(x);
          if (int(k) == iz) v.z() = float(x);
          continue;
        }
        const double cnt = in.read(p.count_type);
        if (!(cnt >= 0) || cnt > 1e6) throw InputError(path, "PLY list with a bad length");
        const std::size_t n = static_cast<std::size_t>(cnt);
        if (format != Format::ascii && n * type_size(p.type) > in.remaining())
          throw InputError(path, "PLY data ends early (truncated file)");
        poly.clear();
        for (std::size_t i = 0; i < n; ++i) {
          const double index = in.read(p.type);
          // checked before the cast: a float list entry may be NaN or huge (UB to convert), found by fuzzing
          if (!(index >= -1.0 && index <= 9.0e15)) throw InputError(path, "PLY list entry is not a valid index");
          poly.push_back(static_cast<long long>(index));
        }
        if (int(k) != iface) continue;
        for (std::size_t i = 0; i < n; ++i)
          if (poly[i] < 0 || poly[i] >= static_cast<long long>(mesh.vertices.size()))
            throw InputError(path, "PLY face refers to a vertex that does not exist");
        for (std::size_t i = 2; i < n; ++i)  // fan triangulation of a convex polygon
          mesh.triangles.emplace_back(int(poly[0]), int(poly[i - 1]), int(poly[i]));
      }
      if (is_vertex) mesh.vertices.push_back(v);
    }
  }
  if (!have_vertices) throw InputError(path, "PLY file has no vertex element");
  return mesh;
}

}  // namespace ewis::detail
