#include <gtest/gtest.h>

#include <cmath>

#include "ewis/core/error.hpp"
#include "ewis/io/cloud_io.hpp"
#include "io/io_test_util.hpp"

using namespace ewis;
using namespace io_test;

namespace {

void expect_same(const Cloud& a, const Cloud& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.normals.size(), b.normals.size());
  ASSERT_EQ(a.colors.size(), b.colors.size());
  ASSERT_EQ(a.intensities.size(), b.intensities.size());
  ASSERT_EQ(a.scalars.size(), b.scalars.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.points[i], b.points[i]) << i;
    if (a.has_normals()) {
      EXPECT_EQ(a.normals[i], b.normals[i]) << i;
    }
    if (a.has_colors()) {
      EXPECT_EQ(a.colors[i], b.colors[i]) << i;
    }
    if (a.has_intensities()) {
      EXPECT_EQ(a.intensities[i], b.intensities[i]) << i;
    }
  }
  for (std::size_t k = 0; k < a.scalars.size(); ++k) {
    EXPECT_EQ(a.scalars[k].name, b.scalars[k].name);
    EXPECT_EQ(a.scalars[k].values, b.scalars[k].values);
  }
}

// A vertex element "x y z" of the given type plus a face element with a list, placed before the vertices
// when `faces_first` (the reader must skip it), and a range_grid after.
std::vector<PlyElem> bunny_like(const std::string& xyz_type, bool faces_first, std::size_t n) {
  PlyElem v{"vertex", {{"x", xyz_type, ""}, {"y", xyz_type, ""}, {"z", xyz_type, ""}}, {}};
  for (std::size_t i = 0; i < n; ++i) v.records.push_back({0.5 * double(i), -1.25 * double(i), 3.0 + double(i)});
  PlyElem f{"face", {{"flags", "uchar", ""}, {"vertex_indices", "int", "uchar"}}, {}};
  f.records = {{7, 3, 0, 1, 2}, {1, 0}, {2, 4, 0, 1, 2, 3}};
  PlyElem g{"range_grid", {{"vertex_indices", "uint", "ushort"}}, {}};
  g.records = {{1, 5}, {0}, {2, 1, 2}};
  if (faces_first) return {f, v, g};
  return {v, f, g};
}

}  // namespace

TEST(Ply, WriteReadRoundTripKeepsEveryAttribute) {
  const Cloud c = sample_cloud(257);
  const std::string p = tmp_dir() + "/roundtrip.ply";
  write_ply(c, p);
  const CloudFile f = read_cloud(p);
  expect_same(c, f.cloud);
  EXPECT_EQ(f.dropped_nonfinite, 0u);
  EXPECT_EQ(f.fields, (std::vector<std::string>{"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue",
                                                "intensity", "curvature"}));
  EXPECT_EQ(f.width, 257u);
  EXPECT_EQ(f.height, 1u);
}

TEST(Ply, WriteReadEmptyAndXyzOnly) {
  const std::string p = tmp_dir() + "/empty.ply";
  write_ply(Cloud{}, p);
  EXPECT_TRUE(read_cloud(p).cloud.empty());
  const Cloud c = sample_cloud(5, false);
  write_ply(c, p);
  expect_same(c, read_cloud(p).cloud);
}

TEST(Ply, EveryEncodingAndCoordinateTypeWithSkippedElements) {
  for (const std::string fmt : {"ascii", "binary_little_endian", "binary_big_endian"})
    for (const std::string type : {"float", "double", "float32", "float64", "int", "short", "int16", "uint8"})
      for (bool faces_first : {true, false}) {
        SCOPED_TRACE(fmt + " " + type + (faces_first ? " faces first" : " faces after"));
        const std::size_t n = type == "uint8" ? 0 : 40;  // uint8 cannot hold the negative y: test an empty body
        const std::string p = write_bytes("enc.ply", encode_ply(fmt, bunny_like(type, faces_first, n)));
        const CloudFile f = read_cloud(p);
        ASSERT_EQ(f.cloud.size(), n);
        for (std::size_t i = 0; i < n; ++i) {
          const bool integral = type != "float" && type != "double" && type != "float32" && type != "float64";
          const double x = integral ? std::trunc(0.5 * double(i)) : 0.5 * double(i);
          const double y = integral ? std::trunc(-1.25 * double(i)) : -1.25 * double(i);
          EXPECT_FLOAT_EQ(f.cloud.points[i].x(), float(x));
          EXPECT_FLOAT_EQ(f.cloud.points[i].y(), float(y));
          EXPECT_FLOAT_EQ(f.cloud.points[i].z(), float(3.0 + double(i)));
        }
        EXPECT_EQ(f.fields, (std::vector<std::string>{"x", "y", "z"}));
      }
}

TEST(Ply, AttributesByTheirUsualNamesAndOtherPropertiesAsScalars) {
  for (const std::string fmt : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(fmt);
    PlyElem v{"vertex",
              {{"x", "double", ""}, {"y", "double", ""}, {"z", "double", ""}, {"normal_x", "float", ""},
               {"normal_y", "float", ""}, {"normal_z", "float", ""}, {"diffuse_red", "uchar", ""},
               {"diffuse_green", "uchar", ""}, {"diffuse_blue", "uchar", ""}, {"alpha", "uchar", ""},
               {"scalar_intensity", "ushort", ""}, {"confidence", "char", ""}, {"tag", "uint", ""}},
              {}};
    for (int i = 0; i < 10; ++i)
      v.records.push_back({1.0 * i, 2.0 * i, 3.0 * i, 0, 0, 1, double(10 * i), double(20 * i), 255, 128,
                           double(1000 + i), double(-i), double(4000000000.0)});
    const CloudFile f = read_cloud(write_bytes("attrs.ply", encode_ply(fmt, {v})));
    ASSERT_EQ(f.cloud.size(), 10u);
    ASSERT_TRUE(f.cloud.has_normals());
    ASSERT_TRUE(f.cloud.has_colors());
    ASSERT_TRUE(f.cloud.has_intensities());
    ASSERT_EQ(f.cloud.scalars.size(), 3u);
    EXPECT_EQ(f.cloud.scalars[0].name, "alpha");
    EXPECT_EQ(f.cloud.scalars[1].name, "confidence");
    EXPECT_EQ(f.cloud.scalars[2].name, "tag");
    for (int i = 0; i < 10; ++i) {
      EXPECT_EQ(f.cloud.normals[i], Eigen::Vector3f(0, 0, 1));
      EXPECT_EQ(f.cloud.colors[i], (Rgb{std::uint8_t(10 * i), std::uint8_t(20 * i), 255}));
      EXPECT_EQ(f.cloud.intensities[i], float(1000 + i));
      EXPECT_EQ(f.cloud.scalars[1].values[i], float(-i));
      EXPECT_EQ(f.cloud.scalars[2].values[i], 4e9f);
    }
    EXPECT_EQ(f.fields.size(), 13u);
    EXPECT_EQ(f.fields[6], "diffuse_red");
  }
}

TEST(Ply, ShortColourNamesAndIncompleteTriplesStayScalars) {
  PlyElem v{"vertex",
            {{"x", "float", ""}, {"y", "float", ""}, {"z", "float", ""}, {"r", "uchar", ""}, {"g", "uchar", ""},
             {"b", "uchar", ""}, {"nx", "float", ""}},
            {{1, 2, 3, 4, 5, 6, 0.5}}};
  const CloudFile f = read_cloud(write_bytes("rgb.ply", encode_ply("binary_little_endian", {v})));
  ASSERT_TRUE(f.cloud.has_colors());
  EXPECT_EQ(f.cloud.colors[0], (Rgb{4, 5, 6}));
  EXPECT_FALSE(f.cloud.has_normals());  // only nx: kept as a scalar named nx
  ASSERT_EQ(f.cloud.scalars.size(), 1u);
  EXPECT_EQ(f.cloud.scalars[0].name, "nx");
  EXPECT_EQ(f.cloud.scalars[0].values[0], 0.5f);
}

TEST(Ply, FastPathWithPaddingAndVertexListProperty) {
  // float x y z not at offset 0, extra data after: the strided fast path.
  PlyElem v{"vertex", {{"id", "int", ""}, {"x", "float", ""}, {"y", "float", ""}, {"z", "float", ""},
                       {"w", "double", ""}}, {}};
  for (int i = 0; i < 100; ++i) v.records.push_back({double(i), i * 0.5, i * 0.25, -i * 1.0, i * 2.0});
  CloudFile f = read_cloud(write_bytes("stride.ply", encode_ply("binary_little_endian", {v})));
  ASSERT_EQ(f.cloud.size(), 100u);
  EXPECT_EQ(f.cloud.points[99], Eigen::Vector3f(49.5f, 24.75f, -99.0f));
  EXPECT_EQ(f.cloud.scalars[1].values[99], 198.0f);
  // A list property inside the vertex element: the per-record walk.
  PlyElem w{"vertex", {{"x", "float", ""}, {"nbrs", "uint", "uchar"}, {"y", "float", ""}, {"z", "double", ""}},
            {{1, 2, 7, 8, 3, 4}, {5, 0, 6, 7}, {8, 3, 1, 2, 3, 9, 10}}};
  for (const std::string fmt : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(fmt);
    f = read_cloud(write_bytes("vlist.ply", encode_ply(fmt, {w})));
    ASSERT_EQ(f.cloud.size(), 3u);
    EXPECT_EQ(f.cloud.points[0], Eigen::Vector3f(1, 3, 4));
    EXPECT_EQ(f.cloud.points[1], Eigen::Vector3f(5, 6, 7));
    EXPECT_EQ(f.cloud.points[2], Eigen::Vector3f(8, 9, 10));
  }
}

TEST(Ply, NonFinitePointsAreDroppedAndCounted) {
  PlyElem v{"vertex", {{"x", "float", ""}, {"y", "float", ""}, {"z", "float", ""}, {"q", "float", ""}},
            {{1, 2, 3, 10}, {NAN, 0, 0, 11}, {4, INFINITY, 6, 12}, {7, 8, 9, 13}, {0, 0, -INFINITY, 14}}};
  for (const std::string fmt : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(fmt);
    const CloudFile f = read_cloud(write_bytes("nan.ply", encode_ply(fmt, {v})));
    EXPECT_EQ(f.dropped_nonfinite, 3u);
    ASSERT_EQ(f.cloud.size(), 2u);
    EXPECT_EQ(f.cloud.points[1], Eigen::Vector3f(7, 8, 9));
    EXPECT_EQ(f.cloud.scalars[0].values, (std::vector<float>{10, 13}));
  }
  // A double too large for float is not a finite float point.
  PlyElem d{"vertex", {{"x", "double", ""}, {"y", "double", ""}, {"z", "double", ""}}, {{1e300, 0, 0}, {1, 1, 1}}};
  const CloudFile f = read_cloud(write_bytes("big.ply", encode_ply("binary_little_endian", {d})));
  EXPECT_EQ(f.cloud.size(), 1u);
  EXPECT_EQ(f.dropped_nonfinite, 1u);
}

TEST(Ply, BadInputsThrowInputError) {
  const std::string good = encode_ply("binary_little_endian", bunny_like("float", true, 20));
  const auto bad = [](const std::string& name, const std::string& bytes) {
    const std::string p = write_bytes(name, bytes);
    EXPECT_THROW(read_cloud(p), InputError) << name;
  };
  bad("trunc.ply", good.substr(0, good.size() - 200));            // body cut inside the vertices
  bad("trunc_faces.ply", good.substr(0, good.find("end_header") + 20));  // cut inside the faces
  bad("noend.ply", good.substr(0, good.find("end_header")));
  bad("magic.ply", "plx\nformat ascii 1.0\nend_header\n");
  bad("nofmt.ply", "ply\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n");
  bad("fmt.ply", "ply\nformat binary_middle_endian 1.0\nelement vertex 0\nproperty float x\nend_header\n");
  bad("type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nproperty float y\nproperty float z\n"
                  "end_header\n1 2 3\n");
  bad("listtype.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                      "property list float int q\nend_header\n1 2 3 0\n");
  bad("noxyz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n");
  bad("novertex.ply", "ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n");
  bad("garbage.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                     "end_header\n1 2 3\n4 five 6\n");
  bad("short_ascii.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                         "property float z\nend_header\n1 2 3\n4 5 6\n7 8\n");
  bad("neglist.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list int int v\nelement vertex 1\n"
                     "property float x\nproperty float y\nproperty float z\nend_header\n-1\n1 2 3\n");
  bad("keyword.ply", "ply\nformat ascii 1.0\nelemnt vertex 1\nend_header\n");
  // Header lies: a count far beyond the body, in every encoding: refused before allocating.
  for (const std::string fmt : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    bad("lie_" + fmt + ".ply", "ply\nformat " + fmt + " 1.0\nelement vertex 4000000000000\nproperty float x\n"
                               "property float y\nproperty float z\nend_header\n1 2 3\n");
    bad("lie_face_" + fmt + ".ply", "ply\nformat " + fmt + " 1.0\nelement face 18446744073709551615\n"
                                    "property list uchar int v\nelement vertex 1\nproperty float x\n"
                                    "property float y\nproperty float z\nend_header\n1 2 3\n");
    bad("lie_list_" + fmt + ".ply", "ply\nformat " + fmt + " 1.0\nelement face 1\nproperty list uint double v\n"
                                    "element vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                                    "end_header\n" + (fmt == "ascii" ? std::string("4000000000 1 2\n")
                                                                     : std::string("\xff\xff\xff\x7f", 4)));
  }
  bad("count_overflow.ply", "ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\nproperty float x\n"
                            "property float y\nproperty float z\nend_header\n1 2 3\n");
}

TEST(Ply, EveryPrefixOfAValidFileFailsCleanlyOrReads) {
  // Truncation anywhere (header or body) must give InputError or a valid smaller read, never a crash.
  for (const std::string fmt : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    const std::string good = encode_ply(fmt, bunny_like("double", true, 6));
    for (std::size_t len = 0; len < good.size(); ++len) {
      const std::string p = write_bytes("prefix.ply", good.substr(0, len));
      try {
        const CloudFile f = read_cloud(p);
        EXPECT_LE(f.cloud.size(), 6u);
      } catch (const InputError&) {
      }
    }
  }
}
