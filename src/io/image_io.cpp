// PNG output through stb_image_write (Debian's libstb holds the implementation: no IMPLEMENTATION define here).
#include <stb/stb_image_write.h>

#include <stdexcept>

#include "ewis/io/cloud_io.hpp"
#include "ewis/io/image_io.hpp"

namespace ewis {

namespace {
void append(void* ctx, void* data, int size) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(ctx);
  const auto* p = static_cast<const std::uint8_t*>(data);
  out->insert(out->end(), p, p + size);
}
}  // namespace

std::vector<std::uint8_t> encode_png(const Image& image) {
  if (image.width_px <= 0 || image.height_px <= 0 ||
      image.rgb.size() != std::size_t(image.width_px) * std::size_t(image.height_px) * 3)
    throw std::invalid_argument("encode_png: image size and pixel buffer do not match");
  std::vector<std::uint8_t> out;
  if (!stbi_write_png_to_func(append, &out, image.width_px, image.height_px, 3, image.rgb.data(), image.width_px * 3))
    throw std::runtime_error("encode_png: PNG encoding failed");
  return out;
}

void write_png(const Image& image, const std::string& path) {
  const std::vector<std::uint8_t> png = encode_png(image);
  write_file_atomic(path, png.data(), png.size());
}

std::string base64_encode(const std::vector<std::uint8_t>& bytes) {
  static constexpr char table[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t v = (std::uint32_t(bytes[i]) << 16) | (std::uint32_t(bytes[i + 1]) << 8) | bytes[i + 2];
    out += table[(v >> 18) & 63], out += table[(v >> 12) & 63], out += table[(v >> 6) & 63], out += table[v & 63];
  }
  if (i + 1 == bytes.size()) {
    const std::uint32_t v = std::uint32_t(bytes[i]) << 16;
    out += table[(v >> 18) & 63], out += table[(v >> 12) & 63], out += "==";
  } else if (i + 2 == bytes.size()) {
    const std::uint32_t v = (std::uint32_t(bytes[i]) << 16) | (std::uint32_t(bytes[i + 1]) << 8);
    out += table[(v >> 18) & 63], out += table[(v >> 12) & 63], out += table[(v >> 6) & 63], out += '=';
  }
  return out;
}

}  // namespace ewis
