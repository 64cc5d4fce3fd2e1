#pragma once
#include <gtest/gtest.h>
#include <filesystem>

namespace lego::test {

// ../shared beside the repository: present on developer machines and in CI, optional elsewhere.
inline std::filesystem::path shared_dir() {
  return LEGOLIZATION_SHARED_DIR;
}
inline std::filesystem::path data_dir() {
  return LEGOLIZATION_TEST_DATA;
}

#define SKIP_WITHOUT_SHARED()                                                        \
  do {                                                                               \
    if (!std::filesystem::is_directory(::lego::test::shared_dir() / "ldraw-models")) \
      GTEST_SKIP() << "../shared is absent";                                         \
  } while (0)

}  // namespace lego::test
