#pragma once
#include <filesystem>

namespace lego::bench {

// The force model against the evidence (issue 35, docs/physics.md "Against the evidence"): the
// structures people built (../shared/physical-tests) and the paper's Figure 7 bridges, as this
// model and the formulations it was measured against judge them.
void physics_section(const std::filesystem::path& source, const std::filesystem::path& shared);

}  // namespace lego::bench
