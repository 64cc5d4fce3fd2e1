#include "layout/where_on_model.h"

#include <gtest/gtest.h>

#include "../physics/builders.h"

namespace lego::layout {
namespace {

// A 2 x 8 brick's ground layer, 8 studs wide and 6 deep (lattice z grows towards the back), and
// a second layer of smaller bricks: where each is, in the words a builder counts studs by.
TEST(WhereOnModel, NamesTheLayerAndStudsFromTheNearestEdges) {
  Assembly a;
  const int ground = test::add(a, "3007", 0, 0, 0);  // 2 x 8 along x, front of the layer
  test::add(a, "3007", 0, 0, 4);                     // 2 x 8 at the back
  const int left = test::add(a, "3003", 0, 0, 2);    // 2 x 2 on the left edge, mid-depth
  const int middle = test::add(a, "3003", 3, 0, 2);  // 2 x 2, 3 studs in, 2 from the front
  const int right = test::add(a, "3003", 6, 0, 2);   // on the right edge
  const int corner = test::add(a, "3005", 7, test::kBrick, 5);  // 1 x 1, back right, layer 2
  const int inner = test::add(a, "3005", 2, test::kBrick, 1);
  EXPECT_EQ(where_on_model(a, ground), "along the whole front edge of layer 1");
  EXPECT_EQ(where_on_model(a, left), "on the left edge of layer 1, 2 studs in from the front");
  EXPECT_EQ(where_on_model(a, middle), "in layer 1, 3 studs in from the left and 2 from the front");
  EXPECT_EQ(where_on_model(a, right), "on the right edge of layer 1, 2 studs in from the front");
  // Layer 2's own edges: from x 2 to 8, z 1 to 6.
  EXPECT_EQ(where_on_model(a, corner), "at the back right corner of layer 2");
  EXPECT_EQ(where_on_model(a, inner), "at the front left corner of layer 2");
}

TEST(WhereOnModel, ABrickAcrossItsLayerSaysSo) {
  Assembly a;
  const int whole = test::add(a, "3001", 0, 0, 0);              // 2 x 4: the whole first layer
  const int across = test::add(a, "3010", 0, test::kBrick, 0);  // 1 x 4 along the front of layer 2
  const int behind = test::add(a, "3010", 0, test::kBrick, 3);  // and one 2 studs behind it
  const int deep =
      test::add(a, "3004", 0, 2 * test::kBrick, 0, true);  // 1 x 2 turned: front to back
  test::add(a, "3005", 2, 2 * test::kBrick, 0);
  EXPECT_EQ(where_on_model(a, whole), "filling layer 1");
  EXPECT_EQ(where_on_model(a, across), "along the whole front edge of layer 2");
  EXPECT_EQ(where_on_model(a, behind), "along the whole back edge of layer 2");
  EXPECT_EQ(where_on_model(a, deep), "along the whole left edge of layer 3");
}

}  // namespace
}  // namespace lego::layout
