// XYZ / TXT / PTS / CSV reader: "x y z" per line (space, tab, comma or semicolon between), extra columns
// ignored, '#' and '//' comments and blank lines skipped. A first line of column names ("x,y,z,...") and a
// first line holding only a point count (Leica PTS) are skipped; any other line that does not start with
// three numbers is an error naming the line.
#include <cstring>

#include "cloud_builder.hpp"
#include "ewis/core/error.hpp"
#include "readers.hpp"
#include "text_scan.hpp"

namespace ewis::io_detail {

namespace {

inline bool is_sep(char c) { return c == ' ' || c == '\t' || c == ',' || c == ';' || c == '\r' || c == '\v' || c == '\f'; }

// Up to `max` tokens of one line; returns how many there were in total (counting beyond max).
std::size_t split_line(std::string_view line, std::string_view* tok, std::size_t max) {
  std::size_t n = 0, i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_sep(line[i])) ++i;
    if (i == line.size()) break;
    const std::size_t b = i;
    while (i < line.size() && !is_sep(line[i])) ++i;
    if (n < max) tok[n] = line.substr(b, i - b);
    ++n;
  }
  return n;
}

bool looks_like_names(const std::string_view* tok, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k) {
    double v;
    if (parse_number(tok[k], v)) return false;
  }
  return true;
}

}  // namespace

CloudFile read_xyz(const std::string& path, std::string_view bytes, float to_mm) {
  // Shortest point line is "0 0 0\n": never reserve more than the file could hold.
  std::size_t lines = 1;
  for (const char* p = bytes.data(); (p = static_cast<const char*>(std::memchr(p, '\n', bytes.data() + bytes.size() - p)));
       ++p)
    ++lines;
  std::vector<FieldSpec> specs = {{"x"}, {"y"}, {"z"}};
  Cloud raw;  // filled directly, then moved through the builder's finishing step
  raw.points.reserve(std::min(lines, bytes.size() / 6 + 1));

  std::size_t pos = 0, line_no = 0;
  bool first_data_line = true;
  std::string_view tok[3];
  while (pos < bytes.size()) {
    const std::size_t nl = bytes.find('\n', pos);
    const std::size_t end = nl == std::string_view::npos ? bytes.size() : nl;
    std::string_view line = bytes.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    std::size_t b = 0;
    while (b < line.size() && is_sep(line[b])) ++b;
    line.remove_prefix(b);
    if (line.empty() || line[0] == '#' || line.substr(0, 2) == "//") continue;
    const std::size_t n = split_line(line, tok, 3);
    const bool was_first = first_data_line;
    first_data_line = false;
    if (was_first) {
      std::uint64_t count;
      if (n == 1 && parse_number(tok[0], count)) continue;            // PTS: the point count
      if (looks_like_names(tok, std::min<std::size_t>(n, 3))) continue;  // CSV: column names
    }
    if (n < 3)
      throw InputError(path, "line " + std::to_string(line_no) + ": expected 'x y z', found " + std::to_string(n) +
                                 " value" + (n == 1 ? "" : "s"));
    float v[3];
    for (int k = 0; k < 3; ++k)
      if (!parse_number(tok[k], v[k]))
        throw InputError(path, "line " + std::to_string(line_no) + ": cannot read '" + excerpt(tok[k]) +
                                   "' as a number");
    raw.points.emplace_back(v[0], v[1], v[2]);
  }
  const std::size_t n = raw.points.size();
  CloudBuilder out(specs, n);
  std::size_t ds;
  float* dst = out.float_dest(0, ds);
  if (n) std::memcpy(dst, raw.points.data(), n * sizeof(Eigen::Vector3f));
  raw = {};
  return out.finish({"x", "y", "z"}, n, 1, to_mm);
}

}  // namespace ewis::io_detail
