#pragma once
// Pose files of CONTRACT.md: 16 numbers, a 4x4 row-major matrix (whitespace or commas between them).
#include <string>

#include "ewis/core/pose.hpp"

namespace ewis {

// Throws InputError when the file is missing, has not exactly 16 finite numbers, or is not a rigid
// transform (rotation not orthonormal within 1e-3, determinant not +1, last row not 0 0 0 1).
Pose read_pose(const std::string& path);
Pose parse_pose(const std::string& text, const std::string& path_for_errors);
std::string pose_to_text(const Pose& pose);  // 4 lines of 4 numbers, full precision
void write_pose(const Pose& pose, const std::string& path);  // atomic (temporary file + rename)

}  // namespace ewis
