#pragma once
// Internal to io/: one reader per format, on the file's bytes. Each returns finite points scaled by to_mm.
#include <string>
#include <string_view>

#include "ewis/io/cloud_io.hpp"

namespace ewis::io_detail {

CloudFile read_ply(const std::string& path, std::string_view bytes, float to_mm);
CloudFile read_pcd(const std::string& path, std::string_view bytes, float to_mm);
CloudFile read_xyz(const std::string& path, std::string_view bytes, float to_mm);

}  // namespace ewis::io_detail
