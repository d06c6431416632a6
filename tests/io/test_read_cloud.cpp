#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "ewis/core/error.hpp"
#include "ewis/io/cloud_io.hpp"
#include "io/io_test_util.hpp"

using namespace ewis;
using namespace io_test;

TEST(ReadCloud, UserErrorsAreInputErrorsNamingTheFile) {
  const std::string missing = tmp_dir() + "/does_not_exist.ply";
  try {
    read_cloud(missing);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), missing);
  }
  const std::string dir = tmp_dir() + "/a_dir.pcd";
  std::filesystem::create_directories(dir);
  EXPECT_THROW(read_cloud(dir), InputError);
  EXPECT_THROW(read_cloud(write_bytes("empty.ply", "")), InputError);
  EXPECT_THROW(read_cloud(write_bytes("empty.pcd", "")), InputError);
  EXPECT_THROW(read_cloud(write_bytes("empty.xyz", "")), InputError);
  EXPECT_THROW(read_cloud(write_bytes("cloud.unknown", "hello")), InputError);
  EXPECT_THROW(read_cloud(write_bytes("mesh.obj", "v 1 2 3\n")), InputError);
  EXPECT_THROW(read_cloud(""), InputError);
}

TEST(ReadCloud, ExtensionIsCaseInsensitiveAndUnknownNamesAreSniffed) {
  const Cloud c = sample_cloud(10, false);
  write_ply(c, tmp_dir() + "/UPPER.PLY");
  EXPECT_EQ(read_cloud(tmp_dir() + "/UPPER.PLY").cloud.size(), 10u);
  write_pcd(c, tmp_dir() + "/noext", true);
  EXPECT_EQ(read_cloud(tmp_dir() + "/noext").cloud.size(), 10u);
  write_ply(c, tmp_dir() + "/scan.data");
  EXPECT_EQ(read_cloud(tmp_dir() + "/scan.data").cloud.size(), 10u);
}

TEST(ReadCloud, UnitsApplyToEveryFormat) {
  const Cloud c = sample_cloud(3, false);
  write_ply(c, tmp_dir() + "/u.ply");
  write_pcd(c, tmp_dir() + "/u.pcd");
  for (const std::string& p : {tmp_dir() + "/u.ply", tmp_dir() + "/u.pcd"}) {
    const CloudFile f = read_cloud(p, LengthUnit::Metre);
    EXPECT_FLOAT_EQ(f.cloud.points[2].y(), c.points[2].y() * 1000.0f);
  }
  EXPECT_EQ(unit_to_mm(LengthUnit::Millimetre), 1.0);
  EXPECT_EQ(unit_to_mm(LengthUnit::Metre), 1000.0);
  EXPECT_EQ(unit_to_mm(LengthUnit::Inch), 25.4);
  EXPECT_EQ(parse_length_unit("m"), LengthUnit::Metre);
  EXPECT_EQ(parse_length_unit("in"), LengthUnit::Inch);
  EXPECT_EQ(parse_length_unit("mm"), LengthUnit::Millimetre);
  EXPECT_THROW(parse_length_unit("ft"), InputError);
  EXPECT_THROW(parse_length_unit(""), InputError);
}

TEST(AtomicWrite, ReplacesWholeAndLeavesNoTemporary) {
  const std::string d = tmp_dir() + "/atomic";
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  const std::string p = d + "/out.txt";
  write_file_atomic(p, "first");
  write_file_atomic(p, std::string("second\0x", 8));
  std::ifstream in(p, std::ios::binary);
  const std::string got((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(got, std::string("second\0x", 8));
  std::size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(d)) ++files, (void)e;
  EXPECT_EQ(files, 1u);
  // An unwritable place: InputError, and the old file is untouched.
  EXPECT_THROW(write_file_atomic(d + "/no/such/dir/x.txt", "x"), InputError);
  EXPECT_THROW(write_file_atomic(d, "x"), InputError);  // a directory
  EXPECT_THROW(write_ply(sample_cloud(3), d + "/missing/x.ply"), InputError);
}
