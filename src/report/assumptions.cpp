#include "report/assumptions.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "report/audit.h"

namespace lego::report {
namespace {

std::string plural(size_t n, const char* word) {
  return fmt::format("{} {}{}", n, word, n == 1 ? "" : "s");
}

// "X" or "X and 3 more carried with it": a carried group by its first part.
std::string group_name(const Audit& a, const physics::CarriedGroup& group) {
  std::string name = describe_carried(a, group.carried.front());
  if (group.carried.size() > 1)
    name += fmt::format(" and {} more carried with it", group.carried.size() - 1);
  return name;
}

}  // namespace

std::string Assumptions::summary() const {
  std::vector<std::string> said;
  if (rigid_joints) said.push_back(plural(size_t(rigid_joints), "rigid joint"));
  if (carried)
    said.push_back(fmt::format("{} of {} parts carried ({:.0f}% of the mass)", carried, parts,
                               100 * carried_share()));
  if (left_out) said.push_back(fmt::format("{} left out", left_out));
  std::string out;
  for (const auto& s : said) out += (out.empty() ? "" : "; ") + s;
  return out;
}

Assumptions assumptions_of(const Audit& a) {
  Assumptions out;
  const Assembly& assembly = a.conversion.assembly;
  const auto& r = a.stability;
  out.parts = int(a.model.parts.size());
  out.analysed = int(assembly.bricks.size());
  out.carried = int(assembly.carried.size());
  for (size_t i = 0; i < assembly.bricks.size(); ++i)
    if (r.graph.fixed.empty() || !r.graph.fixed[i])
      out.analysed_mass_g += assembly.bricks[i].mass_g();
  for (const CarriedPart& c : assembly.carried) out.carried_mass_g += c.mass_g;
  for (const auto& s : a.conversion.skipped) {
    if (s.role == PartRole::Copy) continue;
    ++out.left_out;
    const auto& p = a.model.parts[s.part];
    out.deciding.push_back(
        {Assumption::Kind::Unknown,
         fmt::format("{}:{} {} is left out ({}): its weight and connections are unknown",
                     std::filesystem::path(p.file).filename().string(), p.line, p.reference,
                     s.reason)});
  }
  for (const auto& group : r.graph.carried_groups) {
    if (group.assumed_joint()) {
      ++out.rigid_joints;
    } else if (group.joins.size() == 1 && !group.rests) {
      out.deciding.push_back(
          {Assumption::Kind::Held,
           fmt::format("{} hangs on {} by a connection that is not modelled", group_name(a, group),
                       describe_brick(a, group.joins.front()))});
    }
  }
  out.rigid_joints += int(r.graph.lattice_joints.size() + r.graph.pivot_joints.size());
  return out;
}

// The joints as assumptions that can change the verdict, for when the model is not stable
// without them.
std::vector<Assumption> joint_assumptions(const Audit& a) {
  std::vector<Assumption> out;
  const auto& r = a.stability;
  for (const auto& group : r.graph.carried_groups) {
    if (!group.assumed_joint()) continue;
    std::string joins;
    for (size_t k = 0; k < group.joins.size() && k < 3; ++k)
      joins += (k ? ", " : "") + describe_brick(a, group.joins[k]);
    if (group.joins.size() > 3) joins += fmt::format(" and {} more", group.joins.size() - 3);
    out.push_back(
        {Assumption::Kind::Joint, fmt::format("{} ties {} parts together rigidly: {}",
                                              group_name(a, group), group.joins.size(), joins)});
  }
  auto touching = [&](const std::vector<int>& joints, const char* what) {
    for (int k : joints) {
      const auto& c = r.graph.contacts[size_t(k)];
      out.push_back({Assumption::Kind::Joint,
                     fmt::format("{} and {}, {}, touch and are taken as joined rigidly",
                                 describe_brick(a, c.lower), describe_brick(a, c.upper), what)});
    }
  };
  touching(r.graph.lattice_joints, "on two lattices");
  touching(r.graph.pivot_joints, "hinge halves without a line they share");
  return out;
}

}  // namespace lego::report
