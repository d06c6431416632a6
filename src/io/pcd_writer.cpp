// write_pcd: PCD v0.7, DATA binary (records) or binary_compressed (LZF over field-major arrays, as PCL
// writes it), float fields plus PCL's packed "rgb" (float bits 0x00RRGGBB), written atomically.
#include <lzf.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "ewis/io/cloud_io.hpp"
#include "writer_fields.hpp"

namespace ewis {

namespace {

// One 4-byte column per field; get(i, dst) stores point i's value (little-endian).
struct Column {
  std::string name;
  char type = 'F';
  const Cloud* c = nullptr;
  int kind = 0;  // 0..2 point axis, 3..5 normal axis, 6 rgb, 7 intensity, 8+ scalar k-8
  void get(std::size_t i, char* dst) const {
    if (kind < 3) return io_detail::store_le32(dst, &c->points[i][kind]);
    if (kind < 6) return io_detail::store_le32(dst, &c->normals[i][kind - 3]);
    if (kind == 6) {
      const auto& rgb = c->colors[i];
      const std::uint32_t v = (std::uint32_t(rgb[0]) << 16) | (std::uint32_t(rgb[1]) << 8) | rgb[2];
      return io_detail::store_le32(dst, &v);
    }
    if (kind == 7) return io_detail::store_le32(dst, &c->intensities[i]);
    io_detail::store_le32(dst, &c->scalars[static_cast<std::size_t>(kind - 8)].values[i]);
  }
};

}  // namespace

void write_pcd(const Cloud& cloud, const std::string& path, bool compressed) {
  io_detail::check_cloud_attributes(cloud);
  const std::size_t n = cloud.size();
  std::vector<Column> cols;
  const char* axes[3] = {"x", "y", "z"};
  const char* naxes[3] = {"normal_x", "normal_y", "normal_z"};
  for (int a = 0; a < 3; ++a) cols.push_back({axes[a], 'F', &cloud, a});
  if (cloud.has_normals())
    for (int a = 0; a < 3; ++a) cols.push_back({naxes[a], 'F', &cloud, 3 + a});
  if (cloud.has_colors()) cols.push_back({"rgb", 'F', &cloud, 6});
  if (cloud.has_intensities()) cols.push_back({"intensity", 'F', &cloud, 7});
  for (std::size_t k = 0; k < cloud.scalars.size(); ++k)
    cols.push_back({io_detail::header_word(cloud.scalars[k].name, k), 'F', &cloud, 8 + int(k)});

  std::string fields = "FIELDS", size = "SIZE", type = "TYPE", count = "COUNT";
  for (const auto& c : cols) fields += " " + c.name, size += " 4", type += std::string(" ") + c.type, count += " 1";
  std::string out = "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n" + fields + "\n" + size + "\n" + type +
                    "\n" + count + "\nWIDTH " + std::to_string(n) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
                    std::to_string(n) + "\nDATA " + (compressed ? "binary_compressed" : "binary") + "\n";
  const std::size_t rec = 4 * cols.size();
  const std::size_t raw_size = n * rec;
  if (!compressed) {
    const std::size_t h = out.size();
    out.resize(h + raw_size);
    char* p = out.data() + h;
    for (std::size_t i = 0; i < n; ++i)
      for (const auto& c : cols) c.get(i, p), p += 4;
    return write_file_atomic(path, out);
  }
  if (raw_size > 0xF0000000u) throw std::length_error("write_pcd: binary_compressed holds at most 4 GB");
  std::vector<char> raw(raw_size);
  for (std::size_t f = 0; f < cols.size(); ++f) {
    char* p = raw.data() + f * 4 * n;
    for (std::size_t i = 0; i < n; ++i) cols[f].get(i, p + 4 * i);
  }
  // LZF may grow incompressible data by ~3%; lzf_compress reads past inputs shorter than 2 bytes (DESIGN.md),
  // and raw_size is 0 or at least 12 here, so only the empty cloud skips it.
  std::vector<char> comp(raw_size + raw_size / 16 + 64);
  unsigned comp_size = 0;
  if (raw_size >= 2) {
    comp_size = lzf_compress(raw.data(), unsigned(raw_size), comp.data(), unsigned(comp.size()));
    if (comp_size == 0) throw std::runtime_error("write_pcd: LZF compression failed");
  }
  const std::uint32_t sizes[2] = {comp_size, std::uint32_t(raw_size)};
  const std::size_t h = out.size();
  out.resize(h + 8 + comp_size);
  io_detail::store_le32(out.data() + h, &sizes[0]);
  io_detail::store_le32(out.data() + h + 4, &sizes[1]);
  std::memcpy(out.data() + h + 8, comp.data(), comp_size);
  write_file_atomic(path, out);
}

}  // namespace ewis
