// A scratch directory of the running test's own. ctest runs every test as its own process, two at a time in CI, so
// tests that wrote the same file name into a shared folder raced: ReadObjMesh's "comments.obj" was written by two
// tests at once and one of them read the other's file (a CI failure on a clean clone).
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace ewis::test {

// EWIS_TEST_TMP/<area>/<Suite.Test>, created; parameterised tests' '/' become '_'.
inline std::filesystem::path own_tmp_dir(const std::string& area) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : std::string("no_test");
  for (char& c : name)
    if (c == '/') c = '_';
  const std::filesystem::path dir = std::filesystem::path(EWIS_TEST_TMP) / area / name;
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace ewis::test
