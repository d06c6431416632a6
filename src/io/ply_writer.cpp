// write_ply: binary little-endian PLY, float x y z, then the attributes the cloud has (nx ny nz float,
// red green blue uchar, intensity float, each scalar field float), written atomically.
#include <algorithm>
#include <cstring>
#include <string>

#include "ewis/io/cloud_io.hpp"
#include "writer_fields.hpp"

namespace ewis {

void write_ply(const Cloud& cloud, const std::string& path) {
  io_detail::check_cloud_attributes(cloud);
  const std::size_t n = cloud.size();
  std::string header = "ply\nformat binary_little_endian 1.0\ncomment ewis-inspect, units mm\nelement vertex " +
                       std::to_string(n) + "\nproperty float x\nproperty float y\nproperty float z\n";
  std::size_t rec = 12;
  if (cloud.has_normals()) header += "property float nx\nproperty float ny\nproperty float nz\n", rec += 12;
  if (cloud.has_colors()) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n", rec += 3;
  if (cloud.has_intensities()) header += "property float intensity\n", rec += 4;
  for (std::size_t k = 0; k < cloud.scalars.size(); ++k)
    header += "property float " + io_detail::header_word(cloud.scalars[k].name, k) + "\n", rec += 4;
  header += "end_header\n";

  // In chunks of 64 k points (1-2 MB): the file is never whole in memory (issue 8: inspect's peak memory).
  constexpr std::size_t kChunk = 65536;
  std::size_t next = 0;
  bool header_done = false;
  write_file_atomic_chunked(path, [&](std::string& out) {
    if (!header_done) {
      out = header;
      header_done = true;
    }
    const std::size_t end = std::min(n, next + kChunk);
    const std::size_t at = out.size();
    out.resize(at + (end - next) * rec);
    char* p = out.data() + at;
    for (std::size_t i = next; i < end; ++i) {
      for (int a = 0; a < 3; ++a) io_detail::store_le32(p, &cloud.points[i][a]), p += 4;
      if (cloud.has_normals())
        for (int a = 0; a < 3; ++a) io_detail::store_le32(p, &cloud.normals[i][a]), p += 4;
      if (cloud.has_colors()) std::memcpy(p, cloud.colors[i].data(), 3), p += 3;
      if (cloud.has_intensities()) io_detail::store_le32(p, &cloud.intensities[i]), p += 4;
      for (const auto& s : cloud.scalars) io_detail::store_le32(p, &s.values[i]), p += 4;
    }
    next = end;
    return next < n;
  });
}

}  // namespace ewis
