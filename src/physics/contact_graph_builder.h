#pragma once
// ContactGraph::build, stage by stage (internal to physics). The stages run in the order build()
// lists them, each in the file that names its subject: contact_graph.cpp (shapes, the ground,
// the indexes, contacts in their order), graph_studs.cpp (studs in receptacles),
// graph_faces.cpp (faces that touch, the ground under parts), graph_carried.cpp (carried parts),
// graph_joints.cpp (Technic and hinge joints, assumed-rigid joints).
#include <map>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "physics/contact_graph.h"
#include "physics/spatial_index.h"
#include "physics/table.h"
#include "physics/world_shape.h"

namespace lego::physics {

// Faces closer than this (LDU) touch; bodies sharing more than this on every axis overlap.
inline constexpr double kTouch = 0.25;
// Faces that share less than this across (LDU) meet along an edge: no contact to push on.
inline constexpr double kMinFace = 1.0;
// A carried part joins what comes within this of its body (PHYSICS.md: 1 LDU).
inline constexpr double kCarriedReach = 1.0;
inline constexpr double kStudPitch = kLduPerStud;

// A contact being gathered: its parts, plane and what meets there.
struct Meeting {
  int lower = kGround, upper = 0, direction = kPlusY;
  double plane = 0;
  bool has_patch = false;
  Rect patch;
  std::vector<Vec3> receptacles;  // engaged, in `upper`
  bool support = false;
  bool turned = false;  // in the lattice frame of `upper`, which is turned (Contact::turned)
  bool across = false;  // studs of one lattice in receptacles of another
};

// `r` grown to cover `add` (`has`: whether r covers anything yet).
void grow(Rect& r, bool& has, const Rect& add);
// A patch of points (a tyre's strip, a carried part's lowest points) made at least kMinFace wide
// each way, about its middle.
void widen_to_min_face(Rect& r);
// A box's extent in the plane across `axis`.
Rect in_plane(const Box& b, int axis);
// The friction points of one engaged stud, where it touches `upper`'s receptacle at `r`.
void add_friction_points(const ReceptacleIndex& all, int upper, const Vec3& r, int facing,
                         std::vector<FrictionPoint>& out);

class ContactGraphBuilder {
 public:
  ContactGraphBuilder(const Assembly& a, GroundMode ground, bool assumed_joints,
                      const Budget* budget, bool friction_points);
  ContactGraph build() &&;

 private:
  // The stages, in the order build() runs them.
  void shape_parts();
  void find_ground();
  void index_parts();
  void engage_studs();
  void engage_studs_across_lattices();
  void touch_faces();
  void stand_on_ground();
  void stand_round_part_on_ground(int brick, const std::vector<Vec3>& outline, double below);
  void gather_carried_parts();
  void merge_faces_into_stud_connections();
  void add_meeting_contacts();
  void join_shafts();
  void tie_carried_joints();
  void join_lattices_and_pivots();

  // Carried parts (graph_carried.cpp): what each touches and bears on, its group's mass and
  // centre, and where a group stands on the ground or a fixed part.
  struct CarriedTouches;
  CarriedTouches carried_touches() const;
  void group_carried(const CarriedTouches& t);
  void support_carried_group(CarriedGroup& group, const CarriedTouches& t);

  // Each pass over the parts counts them again: the count says where in a pass it stopped.
  void check_time(int i) const;
  // Parts meet by their studs and faces only on one lattice (docs/what-it-analyses.md, turned
  // lattices): the brick's turned frame, or -1.
  int frame_of(int i) const;
  int owner(int box_id) const { return box_owner_[size_t(box_id)].first; }
  const Box& box(int id) const;         // in its brick's lattice frame
  OrientedBox model_box(int id) const;  // where the model puts it
  // Calls f(id) for the boxes near `bounds` (the model's lattice frame); ids may repeat.
  template <class F>
  void near_in_model(const Box& bounds, double margin, F&& f) const {
    index_.near(bounds, margin, [&](int id) {
      if (!a_.bricks[size_t(owner(id))].frame) f(id);
    });
    if (any_turned_) turned_index_.near(bounds, margin, f);
  }
  // The meeting of two parts across a plane; `in_model`: in the model's frame, whatever upper's.
  Meeting& meeting(int lower, int upper, int direction, double plane, bool in_model = false);
  // A contact joins the list and both its parts' lists (the ground has none); returns its index.
  int add_contact(const Contact& c);
  bool on_ground(double y) const;
  double clearance(const Vec3& p) const;  // how far above the table a point is

  const Assembly& a_;
  const int n_;
  const bool assumed_joints_;
  const bool friction_points_;  // false: ContactGraph::connections
  const Budget* budget_;
  ContactGraph g_;

  std::vector<WorldShape> shapes_;
  std::vector<double> brick_bottom_;  // each brick's lowest point in the model (lattice frame)
  bool any_turned_ = false;
  std::vector<std::vector<OrientedBox>> carried_boxes_;
  std::vector<std::vector<Vec3>> carried_outline_;
  std::vector<double> carried_bottom_;  // the lowest point of each carried part

  Table table_;
  double ground_y_ = 0;

  ReceptacleIndex receptacles_;
  BoxIndex index_;                              // bodies in their bricks' lattice frames
  BoxIndex turned_index_;                       // turned bricks' bodies where the model puts them
  std::vector<std::pair<int, int>> box_owner_;  // (brick, box of its body)

  // Meetings keyed by (lower, upper, direction, plane, turned): stud engagements and touching
  // faces.
  std::map<std::tuple<int, int, int, int64_t, bool>, Meeting> meetings_;
  std::set<std::pair<int, int>> snapped_across_;  // joined by studs across two lattices
  std::set<std::pair<int, int>> shaft_joined_;    // joined by a Technic or hinge joint
};

}  // namespace lego::physics
