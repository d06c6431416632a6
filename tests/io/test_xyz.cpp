#include <gtest/gtest.h>

#include "ewis/core/error.hpp"
#include "ewis/io/cloud_io.hpp"
#include "io/io_test_util.hpp"

using namespace ewis;
using namespace io_test;

TEST(Xyz, SeparatorsCommentsBlankLinesAndExtraColumns) {
  const std::string s =
      "# a comment\n"
      "\n"
      "1 2 3\n"
      "4\t5\t6\t99 100\n"
      "  7,8,9,255,255,255\r\n"
      "// CloudCompare comment\n"
      "10;11;12\n"
      "+1.5e1 -2.5E-1 .5\n"
      "nan 1 2\n"
      "13 14 15";  // no final newline
  const CloudFile f = read_cloud(write_bytes("mixed.xyz", s));
  ASSERT_EQ(f.cloud.size(), 6u);
  EXPECT_EQ(f.dropped_nonfinite, 1u);
  EXPECT_EQ(f.cloud.points[1], Eigen::Vector3f(4, 5, 6));
  EXPECT_EQ(f.cloud.points[2], Eigen::Vector3f(7, 8, 9));
  EXPECT_EQ(f.cloud.points[3], Eigen::Vector3f(10, 11, 12));
  EXPECT_EQ(f.cloud.points[4], Eigen::Vector3f(15, -0.25f, 0.5f));
  EXPECT_EQ(f.cloud.points[5], Eigen::Vector3f(13, 14, 15));
  EXPECT_EQ(f.fields, (std::vector<std::string>{"x", "y", "z"}));
  EXPECT_FALSE(f.cloud.has_colors());
}

TEST(Xyz, CsvHeaderAndPtsCountLineAreSkipped) {
  CloudFile f = read_cloud(write_bytes("h.csv", "X,Y,Z,Intensity\n1,2,3,4\n5,6,7,8\n"));
  EXPECT_EQ(f.cloud.size(), 2u);
  f = read_cloud(write_bytes("c.pts", "2\n1 2 3 -100 10 20 30\n4 5 6 -200 40 50 60\n"));
  ASSERT_EQ(f.cloud.size(), 2u);
  EXPECT_EQ(f.cloud.points[1], Eigen::Vector3f(4, 5, 6));
}

TEST(Xyz, UnitsScaleToMillimetres) {
  const std::string p = write_bytes("units.txt", "1 2 3\n");
  EXPECT_EQ(read_cloud(p, LengthUnit::Metre).cloud.points[0], Eigen::Vector3f(1000, 2000, 3000));
  EXPECT_FLOAT_EQ(read_cloud(p, LengthUnit::Inch).cloud.points[0].z(), 76.2f);
  EXPECT_EQ(read_cloud(p).cloud.points[0], Eigen::Vector3f(1, 2, 3));
}

TEST(Xyz, GarbageNamesTheLine) {
  const std::string p = write_bytes("garbage.xyz", "1 2 3\n4 5 6\n# c\n7 8 zz\n");
  try {
    read_cloud(p);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 4"), std::string::npos) << e.what();
    EXPECT_EQ(e.file(), p);
  }
  EXPECT_THROW(read_cloud(write_bytes("two.xyz", "1 2 3\n4 5\n")), InputError);
  EXPECT_THROW(read_cloud(write_bytes("bin.xyz", std::string("1 2 3\n\x01\x02\x03\x00\xff", 11))), InputError);
  EXPECT_THROW(read_cloud(write_bytes("half.xyz", "1 2 3\n4 5 6e\n")), InputError);
  // Only comments: a valid, empty cloud.
  EXPECT_TRUE(read_cloud(write_bytes("comments.xyz", "# nothing\n\n")).cloud.empty());
}
