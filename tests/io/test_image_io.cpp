#include <gtest/gtest.h>
#include <stb/stb_image.h>

#include <fstream>

#include "ewis/core/error.hpp"
#include "ewis/io/image_io.hpp"
#include "io/io_test_util.hpp"

using namespace ewis;
using namespace io_test;

namespace {
const std::uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
}

TEST(ImageIo, EncodeAndWritePng) {
  Image img(17, 9, 40);
  img.at(3, 4)[0] = 255;
  const std::vector<std::uint8_t> png = encode_png(img);
  ASSERT_GT(png.size(), 8u);
  EXPECT_TRUE(std::equal(kPngSignature, kPngSignature + 8, png.begin()));
  // IHDR holds width and height, big-endian, at bytes 16..23.
  EXPECT_EQ(png[19], 17);
  EXPECT_EQ(png[23], 9);

  const std::string p = tmp_dir() + "/img.png";
  write_png(img, p);
  std::ifstream in(p, std::ios::binary);
  const std::string got((std::istreambuf_iterator<char>(in)), {});
  ASSERT_EQ(got.size(), png.size());
  EXPECT_TRUE(std::equal(png.begin(), png.end(), reinterpret_cast<const std::uint8_t*>(got.data())));
  EXPECT_THROW(write_png(img, tmp_dir() + "/no/dir/x.png"), InputError);
  EXPECT_THROW(encode_png(Image{}), std::invalid_argument);
}

// Decoded by an independent PNG reader (stb_image), every pixel comes back: smooth ramps, noise, edges, one
// column and one row (the filter's first pixel and first row), odd sizes.
TEST(ImageIo, PngDecodesToTheSamePixels) {
  std::mt19937 rng(5);
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {1, 23}, {31, 1}, {64, 48}, {257, 131}}) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        std::uint8_t* p = img.at(x, y);
        p[0] = static_cast<std::uint8_t>(x * 255 / std::max(1, w - 1));             // ramp
        p[1] = static_cast<std::uint8_t>(rng() & 0xff);                               // noise
        p[2] = static_cast<std::uint8_t>((x / 7 + y / 5) % 2 ? 250 : 3);              // edges
      }
    const std::vector<std::uint8_t> png = encode_png(img);
    int dw = 0, dh = 0, channels = 0;
    std::uint8_t* decoded = stbi_load_from_memory(png.data(), static_cast<int>(png.size()), &dw, &dh, &channels, 3);
    ASSERT_NE(decoded, nullptr) << w << "x" << h << ": " << stbi_failure_reason();
    EXPECT_EQ(dw, w);
    EXPECT_EQ(dh, h);
    EXPECT_EQ(channels, 3);
    EXPECT_TRUE(std::equal(img.rgb.begin(), img.rgb.end(), decoded)) << w << "x" << h;
    stbi_image_free(decoded);
  }
}

TEST(ImageIo, Base64) {
  const auto b = [](const std::string& s) { return base64_encode(std::vector<std::uint8_t>(s.begin(), s.end())); };
  EXPECT_EQ(b(""), "");
  EXPECT_EQ(b("f"), "Zg==");
  EXPECT_EQ(b("fo"), "Zm8=");
  EXPECT_EQ(b("foo"), "Zm9v");
  EXPECT_EQ(b("foob"), "Zm9vYg==");
  EXPECT_EQ(b("fooba"), "Zm9vYmE=");
  EXPECT_EQ(b("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64_encode({0xff, 0xfe, 0x00}), "//4A");
}
