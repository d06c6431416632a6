#pragma once
// Point-cloud files: PLY (ascii, binary LE/BE), PCD v0.5/v0.7 (ascii, binary, binary_compressed/LZF), XYZ/TXT.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "ewis/core/cloud.hpp"

namespace ewis {

enum class LengthUnit { Millimetre, Metre, Inch };
double unit_to_mm(LengthUnit unit);
LengthUnit parse_length_unit(const std::string& text);  // "mm" | "m" | "in"; throws InputError otherwise

struct CloudFile {
  Cloud cloud;                          // finite points only, scaled to mm
  std::vector<std::string> fields;      // the file's fields in file order, e.g. {"x","y","z","rgb"}
  std::size_t dropped_nonfinite = 0;    // points dropped for a NaN/Inf coordinate
  std::size_t width = 0, height = 0;    // organised clouds (PCD WIDTH/HEIGHT); height 1 otherwise
};

// Reads by extension (.ply, .pcd, .xyz, .txt, .pts, .csv); throws InputError(path, what) on anything wrong:
// missing file, directory, empty file, truncated body, header that lies about the count (never allocates
// more than the file can hold), unknown property type, LZF stream that does not decompress, garbage numbers.
CloudFile read_cloud(const std::string& path, LengthUnit unit = LengthUnit::Millimetre);

// Binary little-endian PLY with x y z (float), and nx ny nz, red green blue, intensity, scalars when present.
// Atomic: writes a temporary file beside `path`, then renames it.
void write_ply(const Cloud& cloud, const std::string& path);
// PCD v0.7, binary (or binary_compressed when `compressed`), same fields; atomic.
void write_pcd(const Cloud& cloud, const std::string& path, bool compressed = false);
// Writes a whole file atomically (temporary name beside it, then rename); throws InputError on failure.
void write_file_atomic(const std::string& path, const std::string& contents);
void write_file_atomic(const std::string& path, const void* data, std::size_t size);
// The same, written chunk by chunk as `next` makes them (it gets the chunk cleared and returns false after the
// last one): a large file without its whole image in memory. An exception from `next` leaves no file.
void write_file_atomic_chunked(const std::string& path, const std::function<bool(std::string&)>& next);

}  // namespace ewis
