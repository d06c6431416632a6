#include "writer_fields.hpp"

#include <stdexcept>

namespace ewis::io_detail {

void check_cloud_attributes(const Cloud& c) {
  const std::size_t n = c.points.size();
  const auto ok = [n](std::size_t s) { return s == 0 || s == n; };
  bool good = ok(c.normals.size()) && ok(c.colors.size()) && ok(c.intensities.size());
  for (const auto& s : c.scalars) good = good && s.values.size() == n;
  if (!good) throw std::invalid_argument("Cloud attribute vectors do not match the number of points");
}

std::string header_word(const std::string& name, std::size_t k) {
  std::string w;
  for (char c : name) w += (static_cast<unsigned char>(c) <= 32 || c == 127) ? '_' : c;
  if (w.empty()) w = "scalar" + std::to_string(k);
  return w;
}

}  // namespace ewis::io_detail
