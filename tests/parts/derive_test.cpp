#include <gtest/gtest.h>

#include "parts/part_library.h"
#include "test_paths.h"

namespace lego::parts {
namespace {}  // namespace
}  // namespace lego::parts
