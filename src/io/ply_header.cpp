#include "ply_header.hpp"

#include "ewis/core/error.hpp"
#include "text_scan.hpp"

namespace ewis::io_detail {

namespace {

ScalarType type_or_throw(const std::string& path, std::size_t line, std::string_view name) {
  ScalarType t;
  if (!parse_ply_type(name, t))
    throw InputError(path, "PLY header line " + std::to_string(line) + ": unknown property type '" +
                               excerpt(name) + "'");
  return t;
}

}  // namespace

PlyHeader parse_ply_header(const std::string& path, std::string_view bytes) {
  if (bytes.size() < 4 || bytes.substr(0, 3) != "ply" || (bytes[3] != '\n' && bytes[3] != '\r'))
    throw InputError(path, "not a PLY file (no 'ply' magic line)");
  PlyHeader h;
  bool have_format = false, ended = false;
  std::size_t pos = 0, line_no = 0;
  while (pos < bytes.size() && !ended) {
    std::size_t nl = bytes.find('\n', pos);
    const std::size_t line_end = nl == std::string_view::npos ? bytes.size() : nl;
    std::string_view line = bytes.substr(pos, line_end - pos);
    pos = nl == std::string_view::npos ? bytes.size() : nl + 1;
    ++line_no;
    if (line_no > 100000) break;  // no real header is this long: stop before scanning a binary body
    const auto w = split_words(line);
    if (w.empty()) continue;
    const std::string where = "PLY header line " + std::to_string(line_no) + ": ";
    if (w[0] == "ply" && line_no == 1) continue;
    if (w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      if (w.size() < 2) throw InputError(path, where + "format line without a format");
      if (w[1] == "ascii") h.format = PlyFormat::Ascii;
      else if (w[1] == "binary_little_endian") h.format = PlyFormat::BinaryLittleEndian;
      else if (w[1] == "binary_big_endian") h.format = PlyFormat::BinaryBigEndian;
      else throw InputError(path, where + "unknown format '" + excerpt(w[1]) + "'");
      have_format = true;
    } else if (w[0] == "element") {
      std::uint64_t count = 0;
      if (w.size() != 3) throw InputError(path, where + "expected 'element NAME COUNT'");
      if (!parse_number(w[2], count))
        throw InputError(path, where + "element count '" + excerpt(w[2]) + "' is not a valid count");
      h.elements.push_back({std::string(w[1]), count, {}});
    } else if (w[0] == "property") {
      if (h.elements.empty()) throw InputError(path, where + "property before any element");
      PlyProperty p;
      if (w.size() >= 2 && w[1] == "list") {
        if (w.size() != 5) throw InputError(path, where + "expected 'property list COUNT_TYPE ITEM_TYPE NAME'");
        p.is_list = true;
        p.count_type = type_or_throw(path, line_no, w[2]);
        if (is_float(p.count_type)) throw InputError(path, where + "list count type must be an integer type");
        p.type = type_or_throw(path, line_no, w[3]);
        p.name = std::string(w[4]);
      } else {
        if (w.size() != 3) throw InputError(path, where + "expected 'property TYPE NAME'");
        p.type = type_or_throw(path, line_no, w[1]);
        p.name = std::string(w[2]);
      }
      h.elements.back().properties.push_back(std::move(p));
    } else if (w[0] == "end_header") {
      ended = true;
    } else {
      throw InputError(path, where + "unknown header keyword '" + excerpt(w[0]) + "'");
    }
  }
  if (!ended) throw InputError(path, "PLY header has no end_header line");
  if (!have_format) throw InputError(path, "PLY header has no format line");
  h.body_offset = pos;
  h.body_line = line_no + 1;
  return h;
}

}  // namespace ewis::io_detail
