// read_cloud: dispatch by extension (content sniffing for other names), units to mm.
#include <algorithm>
#include <cctype>

#include "ewis/core/error.hpp"
#include "ewis/io/cloud_io.hpp"
#include "file_bytes.hpp"
#include "readers.hpp"

namespace ewis {

double unit_to_mm(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::Metre: return 1000.0;
    case LengthUnit::Inch: return 25.4;
    default: return 1.0;
  }
}

LengthUnit parse_length_unit(const std::string& text) {
  if (text == "mm") return LengthUnit::Millimetre;
  if (text == "m") return LengthUnit::Metre;
  if (text == "in") return LengthUnit::Inch;
  throw InputError("", "unknown length unit '" + text + "' (expected mm, m or in)");
}

namespace {

std::string lower_extension(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

}  // namespace

CloudFile read_cloud(const std::string& path, LengthUnit unit) {
  const std::string ext = lower_extension(path);
  const bool known = ext == "ply" || ext == "pcd" || ext == "xyz" || ext == "txt" || ext == "pts" || ext == "csv" ||
                     ext == "asc";
  if (!known && !ext.empty() && (ext == "obj" || ext == "stl" || ext == "gltf" || ext == "glb"))
    throw InputError(path, "a mesh, not a point cloud (expected .ply, .pcd, .xyz, .txt, .pts or .csv)");
  const io_detail::FileBytes file = io_detail::read_file_bytes(path);
  const std::string_view bytes = file.view();
  const float to_mm = static_cast<float>(unit_to_mm(unit));
  if (ext == "ply") return io_detail::read_ply(path, bytes, to_mm);
  if (ext == "pcd") return io_detail::read_pcd(path, bytes, to_mm);
  if (known) return io_detail::read_xyz(path, bytes, to_mm);
  // Another name: look at the content.
  if (bytes.substr(0, 3) == "ply") return io_detail::read_ply(path, bytes, to_mm);
  if (bytes.substr(0, 6) == "# .PCD" || bytes.substr(0, 7) == "VERSION") return io_detail::read_pcd(path, bytes, to_mm);
  throw InputError(path, "unknown point cloud format '" + ext + "' (expected .ply, .pcd, .xyz, .txt, .pts or .csv)");
}

}  // namespace ewis
