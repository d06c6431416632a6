#pragma once
// PNG output for pictures (scan renders, viewpoint renders, report figures).
#include <cstdint>
#include <string>
#include <vector>

namespace ewis {

struct Image {
  int width_px = 0, height_px = 0;
  std::vector<std::uint8_t> rgb;  // row-major, 3 bytes a pixel, width*height*3

  Image() = default;
  Image(int w, int h, std::uint8_t fill = 0) : width_px(w), height_px(h), rgb(std::size_t(w) * h * 3, fill) {}
  std::uint8_t* at(int col, int row) { return rgb.data() + (std::size_t(row) * width_px + col) * 3; }
};

// Writes a PNG atomically (temporary file + rename); throws InputError on failure.
void write_png(const Image& image, const std::string& path);
// Encodes a PNG in memory (for embedding in HTML as base64).
std::vector<std::uint8_t> encode_png(const Image& image);
std::string base64_encode(const std::vector<std::uint8_t>& bytes);

}  // namespace ewis
