#include <gtest/gtest.h>

#include "parts/assembly_builder.h"
#include "test_paths.h"

namespace lego::parts {
namespace {}  // namespace
}  // namespace lego::parts
