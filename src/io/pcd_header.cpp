#include "pcd_header.hpp"

#include "ewis/core/error.hpp"
#include "text_scan.hpp"

namespace ewis::io_detail {

namespace {

}  // namespace

PcdHeader parse_pcd_header(const std::string& path, std::string_view bytes) {
  PcdHeader h;
  std::vector<std::string_view> names, sizes, types, counts;
  bool have_width = false, have_height = false, have_points = false, have_data = false, have_fields = false;
  std::uint64_t width = 0, height = 1, points = 0;
  std::size_t pos = 0, line_no = 0;
  while (pos < bytes.size() && !have_data) {
    const std::size_t nl = bytes.find('\n', pos);
    const std::size_t line_end = nl == std::string_view::npos ? bytes.size() : nl;
    const std::string_view line = bytes.substr(pos, line_end - pos);
    pos = nl == std::string_view::npos ? bytes.size() : nl + 1;
    ++line_no;
    if (line_no > 10000) break;  // a header is a dozen lines: stop before scanning a binary body
    const auto w = split_words(line);
    if (w.empty() || w[0][0] == '#') continue;
    const std::string where = "PCD header line " + std::to_string(line_no) + ": ";
    const std::string_view key = w[0];
    const auto one_number = [&](std::uint64_t& out) {
      if (w.size() != 2 || !parse_number(w[1], out)) throw InputError(path, where + "expected '" + std::string(key) + " N'");
    };
    if (key == "VERSION") {
    } else if (key == "FIELDS" || key == "COLUMNS") {
      names.assign(w.begin() + 1, w.end());
      have_fields = true;
    } else if (key == "SIZE") {
      sizes.assign(w.begin() + 1, w.end());
    } else if (key == "TYPE") {
      types.assign(w.begin() + 1, w.end());
    } else if (key == "COUNT") {
      counts.assign(w.begin() + 1, w.end());
    } else if (key == "WIDTH") {
      one_number(width), have_width = true;
    } else if (key == "HEIGHT") {
      one_number(height), have_height = true;
    } else if (key == "POINTS") {
      one_number(points), have_points = true;
    } else if (key == "VIEWPOINT") {
    } else if (key == "DATA") {
      if (w.size() != 2) throw InputError(path, where + "expected 'DATA ascii|binary|binary_compressed'");
      if (w[1] == "ascii") h.data = PcdData::Ascii;
      else if (w[1] == "binary") h.data = PcdData::Binary;
      else if (w[1] == "binary_compressed") h.data = PcdData::BinaryCompressed;
      else throw InputError(path, where + "unknown DATA encoding '" + excerpt(w[1]) + "'");
      have_data = true;
    } else {
      if (!have_fields && line_no <= 2 && key != "VERSION") throw InputError(path, "not a PCD file");
      throw InputError(path, where + "unknown header keyword '" + excerpt(key) + "'");
    }
  }
  if (!have_data) throw InputError(path, "PCD header has no DATA line");
  if (!have_fields || names.empty()) throw InputError(path, "PCD header has no FIELDS");
  if (sizes.size() != names.size())
    throw InputError(path, "PCD header: SIZE has " + std::to_string(sizes.size()) + " entries for " +
                               std::to_string(names.size()) + " FIELDS");
  if (types.size() != names.size())
    throw InputError(path, "PCD header: TYPE has " + std::to_string(types.size()) + " entries for " +
                               std::to_string(names.size()) + " FIELDS");
  if (!counts.empty() && counts.size() != names.size())
    throw InputError(path, "PCD header: COUNT has " + std::to_string(counts.size()) + " entries for " +
                               std::to_string(names.size()) + " FIELDS");
  std::uint64_t point_bytes = 0;
  for (std::size_t i = 0; i < names.size(); ++i) {
    std::uint64_t size = 0, count = 1;
    if (!parse_number(sizes[i], size)) throw InputError(path, "PCD header: bad SIZE '" + excerpt(sizes[i]) + "'");
    if (!counts.empty() && (!parse_number(counts[i], count) || count == 0 || count > (1u << 20)))
      throw InputError(path, "PCD header: bad COUNT '" + excerpt(counts[i]) + "'");
    ScalarType t;
    if (types[i].size() != 1 || !parse_pcd_type(types[i][0], static_cast<std::size_t>(size), t))
      throw InputError(path, "PCD header: unsupported TYPE '" + excerpt(types[i]) + "' with SIZE " +
                                 std::to_string(size) + " for field '" + excerpt(names[i]) + "'");
    h.fields.push_back({std::string(names[i]), t, static_cast<std::size_t>(count)});
    point_bytes += size * count;
  }
  h.point_bytes = static_cast<std::size_t>(point_bytes);
  if (!have_width && !have_points) throw InputError(path, "PCD header has neither WIDTH nor POINTS");
  if (!have_width) width = points, height = 1;
  if (height != 0 && width > (std::uint64_t(1) << 40) / height)
    throw InputError(path, "PCD header: WIDTH x HEIGHT is absurdly large");
  if (!have_points) points = width * height;
  if (width * height != points)
    throw InputError(path, "PCD header: POINTS " + std::to_string(points) + " does not match WIDTH x HEIGHT " +
                               std::to_string(width) + " x " + std::to_string(height));
  (void)have_height;
  h.width = static_cast<std::size_t>(width);
  h.height = static_cast<std::size_t>(height);
  h.points = static_cast<std::size_t>(points);
  h.body_offset = pos;
  h.body_line = line_no + 1;
  return h;
}

}  // namespace ewis::io_detail
