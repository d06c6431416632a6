#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ewis/core/error.hpp"
#include "ewis/io/cloud_io.hpp"
#include "io/io_test_util.hpp"

using namespace ewis;
using namespace io_test;

namespace {

std::string header(const std::string& fields, const std::string& size, const std::string& type,
                   const std::string& count, std::size_t w, std::size_t h, const std::string& data,
                   bool v05 = false) {
  std::string s = v05 ? "# .PCD v.5 - Point Cloud Data file format\nVERSION .5\n"
                      : "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n";
  s += "FIELDS " + fields + "\nSIZE " + size + "\nTYPE " + type + "\n";
  if (!count.empty()) s += "COUNT " + count + "\n";
  s += "WIDTH " + std::to_string(w) + "\nHEIGHT " + std::to_string(h) + "\n";
  if (!v05) s += "VIEWPOINT 0 0 0 1 0 0 0\n";
  s += "POINTS " + std::to_string(w * h) + "\nDATA " + data + "\n";
  return s;
}

template <class T>
void put(std::string& s, T v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof v);
}

}  // namespace

TEST(Pcd, WriteReadRoundTripBinaryAndCompressed) {
  const Cloud c = sample_cloud(1000);
  for (bool compressed : {false, true}) {
    SCOPED_TRACE(compressed ? "binary_compressed" : "binary");
    const std::string p = tmp_dir() + "/roundtrip.pcd";
    write_pcd(c, p, compressed);
    const CloudFile f = read_cloud(p);
    ASSERT_EQ(f.cloud.size(), c.size());
    for (std::size_t i = 0; i < c.size(); ++i) {
      EXPECT_EQ(f.cloud.points[i], c.points[i]);
      EXPECT_EQ(f.cloud.normals[i], c.normals[i]);
      EXPECT_EQ(f.cloud.colors[i], c.colors[i]);
      EXPECT_EQ(f.cloud.intensities[i], c.intensities[i]);
    }
    ASSERT_EQ(f.cloud.scalars.size(), 1u);
    EXPECT_EQ(f.cloud.scalars[0].name, "curvature");
    EXPECT_EQ(f.cloud.scalars[0].values, c.scalars[0].values);
    EXPECT_EQ(f.fields, (std::vector<std::string>{"x", "y", "z", "normal_x", "normal_y", "normal_z", "rgb",
                                                  "intensity", "curvature"}));
  }
}

TEST(Pcd, WriteReadTinyClouds) {
  for (std::size_t n : {0, 1, 2}) {
    const Cloud c = sample_cloud(n, false);
    for (bool compressed : {false, true}) {
      const std::string p = tmp_dir() + "/tiny.pcd";
      write_pcd(c, p, compressed);
      const CloudFile f = read_cloud(p);
      ASSERT_EQ(f.cloud.size(), n);
      for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(f.cloud.points[i], c.points[i]);
    }
  }
}

TEST(Pcd, AsciiV05WithoutViewpointAndNan) {
  const std::string s = header("x y z", "4 4 4", "F F F", "1 1 1", 4, 1, "ascii", true) +
                        "1 2 3\n0.5 -0.25 1e-3\nnan nan nan\n+4 5 6\n";
  const CloudFile f = read_cloud(write_bytes("v05.pcd", s), LengthUnit::Metre);
  ASSERT_EQ(f.cloud.size(), 3u);
  EXPECT_EQ(f.dropped_nonfinite, 1u);
  EXPECT_FLOAT_EQ(f.cloud.points[1].y(), -250.0f);
  EXPECT_FLOAT_EQ(f.cloud.points[1].z(), 1.0f);
  EXPECT_FLOAT_EQ(f.cloud.points[2].x(), 4000.0f);
  EXPECT_EQ(f.width, 4u);
}

TEST(Pcd, PackedColourAsFloatOrUintAndMultiCountFieldsSkipped) {
  const std::uint32_t packed = 0xFF102030u;  // a r g b
  float as_float;
  std::memcpy(&as_float, &packed, 4);
  // Binary, rgba as U, with a 3-value histogram and a double scalar.
  std::string b = header("x y z rgba hist q", "4 4 4 4 2 8", "F F F U U F", "1 1 1 1 3 1", 2, 1, "binary");
  for (int i = 0; i < 2; ++i) {
    put(b, 1.0f * i), put(b, 2.0f), put(b, 3.0f), put(b, packed);
    put(b, std::uint16_t(1)), put(b, std::uint16_t(2)), put(b, std::uint16_t(3)), put(b, 0.125 * i);
  }
  CloudFile f = read_cloud(write_bytes("rgba.pcd", b));
  ASSERT_EQ(f.cloud.size(), 2u);
  EXPECT_EQ(f.cloud.colors[1], (Rgb{0x10, 0x20, 0x30}));
  EXPECT_EQ(f.fields, (std::vector<std::string>{"x", "y", "z", "rgba", "hist", "q"}));
  ASSERT_EQ(f.cloud.scalars.size(), 1u);
  EXPECT_EQ(f.cloud.scalars[0].name, "q");
  EXPECT_EQ(f.cloud.scalars[0].values[1], 0.125f);
  EXPECT_EQ(f.cloud.points[1], Eigen::Vector3f(1, 2, 3));
  // Ascii, rgb as F (the float's bits), as PCL writes XYZRGB.
  char num[64];
  std::snprintf(num, sizeof num, "%.9g", double(std::abs(as_float) > 0 ? as_float : 0));
  const std::uint32_t packed2 = 0x00A0B0C0u;
  float f2;
  std::memcpy(&f2, &packed2, 4);
  std::snprintf(num, sizeof num, "%.9g", double(f2));
  const std::string a = header("x y z rgb", "4 4 4 4", "F F F F", "", 1, 1, "ascii") + "1 2 3 " + num + "\n";
  f = read_cloud(write_bytes("rgbf.pcd", a));
  ASSERT_EQ(f.cloud.size(), 1u);
  EXPECT_EQ(f.cloud.colors[0], (Rgb{0xA0, 0xB0, 0xC0}));
}

TEST(Pcd, OrganisedCloudWithNansKeepsWidthHeight) {
  Cloud c;
  std::string b = header("x y z _", "4 4 4 4", "F F F U", "1 1 1 1", 4, 3, "binary");
  std::size_t nans = 0;
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 4; ++col) {
      const bool hole = (r + col) % 3 == 0;
      nans += hole;
      put(b, hole ? NAN : float(col)), put(b, float(r)), put(b, 1.0f), put(b, std::uint32_t(0));
    }
  const CloudFile f = read_cloud(write_bytes("organised.pcd", b));
  EXPECT_EQ(f.width, 4u);
  EXPECT_EQ(f.height, 3u);
  EXPECT_EQ(f.dropped_nonfinite, nans);
  EXPECT_EQ(f.cloud.size() + nans, 12u);
  EXPECT_EQ(f.fields, (std::vector<std::string>{"x", "y", "z"}));
}

TEST(Pcd, BadInputsThrowInputError) {
  const auto bad = [](const std::string& name, const std::string& bytes) {
    EXPECT_THROW(read_cloud(write_bytes(name, bytes)), InputError) << name;
  };
  std::string b = header("x y z", "4 4 4", "F F F", "1 1 1", 10, 1, "binary");
  for (int i = 0; i < 9; ++i) put(b, 1.0f), put(b, 2.0f), put(b, 3.0f);
  bad("trunc.pcd", b);  // 9 of 10 points
  bad("lie.pcd", header("x y z", "4 4 4", "F F F", "", 1000000000000, 1, "binary") + "abc");
  bad("lie_ascii.pcd", header("x y z", "4 4 4", "F F F", "", 1000000000, 1, "ascii") + "1 2 3\n");
  bad("lie_comp.pcd", header("x y z", "4 4 4", "F F F", "", 1000000000, 1, "binary_compressed") + "abc");
  std::string mism = header("x y z", "4 4 4", "F F F", "", 2, 1, "binary");
  mism.replace(mism.find("POINTS 2"), 8, "POINTS 3");
  bad("points_mismatch.pcd", mism + std::string(36, '\0'));
  bad("size_count.pcd", header("x y z", "4 4", "F F F", "", 1, 1, "ascii") + "1 2 3\n");
  bad("type.pcd", header("x y z", "4 4 3", "F F F", "", 1, 1, "ascii") + "1 2 3\n");
  bad("type2.pcd", header("x y z", "4 4 4", "F F X", "", 1, 1, "ascii") + "1 2 3\n");
  bad("count0.pcd", header("x y z", "4 4 4", "F F F", "1 0 1", 1, 1, "ascii") + "1 2 3\n");
  bad("noxyz.pcd", header("a b c", "4 4 4", "F F F", "", 1, 1, "ascii") + "1 2 3\n");
  bad("nodata.pcd", "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\n");
  bad("data.pcd", header("x y z", "4 4 4", "F F F", "", 1, 1, "zip") + "1 2 3\n");
  bad("garbage.pcd", header("x y z", "4 4 4", "F F F", "", 2, 1, "ascii") + "1 2 3\n4 x 6\n");
  bad("short.pcd", header("x y z", "4 4 4", "F F F", "", 2, 1, "ascii") + "1 2 3\n4 5\n");
  bad("notpcd.pcd", "hello world\n");
  // binary_compressed: sizes that lie and streams that do not decompress.
  const std::string h = header("x y z", "4 4 4", "F F F", "", 2, 1, "binary_compressed");
  std::string c1 = h;
  put(c1, std::uint32_t(1000)), put(c1, std::uint32_t(24)), c1 += "abcdefgh";
  bad("comp_size.pcd", c1);
  std::string c2 = h;
  put(c2, std::uint32_t(4)), put(c2, std::uint32_t(30)), c2 += "abcd";
  bad("raw_size.pcd", c2);
  std::string c3 = h;
  put(c3, std::uint32_t(4)), put(c3, std::uint32_t(24)), c3 += "\xff\xff\xff\xff";
  bad("lzf.pcd", c3);
  std::string c4 = h;
  put(c4, std::uint32_t(2));
  bad("comp_short.pcd", c4);
}

TEST(Pcd, CorruptedCompressedFilesNeverCrash) {
  const std::string p = tmp_dir() + "/fuzz_src.pcd";
  write_pcd(sample_cloud(300), p, true);
  std::string good;
  {
    std::ifstream in(p, std::ios::binary);
    good.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::mt19937 rng(12345);
  for (int trial = 0; trial < 300; ++trial) {
    std::string s = good;
    const int flips = 1 + int(rng() % 8);
    for (int k = 0; k < flips; ++k) s[rng() % s.size()] = char(rng());
    if (trial % 3 == 0) s.resize(rng() % s.size());
    try {
      const CloudFile f = read_cloud(write_bytes("fuzz.pcd", s));
      EXPECT_LE(f.cloud.size(), 300u * 100);
    } catch (const InputError&) {
    }
  }
}
