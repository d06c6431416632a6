#include <gtest/gtest.h>

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
