#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace lego::test {

// ../shared beside the repository: present on developer machines and in CI, optional elsewhere.
inline std::filesystem::path shared_dir() {
  return LEGOLIZATION_SHARED_DIR;
}
inline std::filesystem::path data_dir() {
  return LEGOLIZATION_TEST_DATA;
}

// A scratch directory of the running test's own (named after it), so tests that ctest runs in
// parallel never share files; `name` inside it.
inline std::filesystem::path scratch(const std::string& prefix, const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() /
             (prefix + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
  std::filesystem::create_directories(dir);
  return dir / name;
}

#define SKIP_WITHOUT_SHARED()                                                        \
  do {                                                                               \
    if (!std::filesystem::is_directory(::lego::test::shared_dir() / "ldraw-models")) \
      GTEST_SKIP() << "../shared is absent";                                         \
  } while (0)

}  // namespace lego::test
