#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
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

// An LDraw library for the tests that need only official parts: $LDRAWDIR (the LDraw tools'
// convention) when it holds one, else ../shared/ldraw-library. Tests of the shared models use
// the shared library, whose parts their numbers were measured with.
inline std::filesystem::path ldraw_library() {
  const char* env = std::getenv("LDRAWDIR");
  if (env && *env && std::filesystem::is_directory(std::filesystem::path(env) / "parts"))
    return env;
  return shared_dir() / "ldraw-library";
}

#define SKIP_WITHOUT_LIBRARY()                                                             \
  do {                                                                                     \
    if (!std::filesystem::is_directory(::lego::test::ldraw_library() / "parts"))           \
      GTEST_SKIP() << "no LDraw library: set LDRAWDIR, or put ../shared beside the project"; \
  } while (0)

#define SKIP_WITHOUT_SHARED()                                                        \
  do {                                                                               \
    if (!std::filesystem::is_directory(::lego::test::shared_dir() / "ldraw-models")) \
      GTEST_SKIP() << "../shared is absent";                                         \
  } while (0)

}  // namespace lego::test
