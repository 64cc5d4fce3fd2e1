#pragma once
// Where a booklet's picture looks at each step: a LeoCAD camera with a key per step, written into
// the file LeoCAD renders, so that one run draws every step framed as it needs (LeoCAD keeps a
// camera's position, target and up vector per step: `0 !LEOCAD CAMERA POSITION_KEY step x y z`).
// Each step is seen from the booklet's one direction (30 degrees up, 45 around, as the cover) and
// framed on the model so far; where its new parts are a small part of that, on them and around
// them, so that a window put into a wall is seen, not a speck on a house.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/part_shape.h"
#include "ldraw/reader.h"

namespace lego::report {

// A box in LDraw's frame (LDU, -y up).
struct FrameBox {
  std::array<double, 3> min{1e300, 1e300, 1e300}, max{-1e300, -1e300, -1e300};
  bool empty() const { return min[0] > max[0]; }
  void add(const std::array<double, 3>& p);
  void add(const FrameBox& b);
  std::array<double, 3> centre() const;
  double radius() const;  // half the diagonal
};

// The space a placed part takes, near enough to frame it: its body in its own frame when known
// (what brickcheck derived of it), else a catalog part's, else a box of two studs around its
// origin.
FrameBox part_box(const ldraw::PlacedPart& part, const std::optional<Box>& body = std::nullopt);

// What a step's picture frames: a sphere.
struct Frame {
  std::array<double, 3> centre{0, 0, 0};
  double radius = 0;
};
// The model so far, or, where the step's new parts take less than a third of it, a sphere around
// them a third of its size.
Frame frame_step(const FrameBox& new_parts, const FrameBox& so_far);

inline constexpr const char* kStepCamera = "Booklet";
inline constexpr const char* kCoverCamera = "Cover";
// LeoCAD's lines for a camera `name` with a key for each frame (step k is frames[k-1]).
std::string camera_lines(const std::string& name, const std::vector<Frame>& frames);
// The camera kStepCamera.
inline std::string step_camera(const std::vector<Frame>& frames) {
  return camera_lines(kStepCamera, frames);
}

}  // namespace lego::report
