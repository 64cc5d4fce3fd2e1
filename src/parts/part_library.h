#pragma once
// Part knowledge, derived once per part file and cached for the process (PHYSICS.md "Parts").
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/brick_catalog.h"
#include "ldraw/reader.h"
#include "parts/derive.h"
#include "parts/part_files.h"
#include "parts/part_geometry.h"

namespace lego::parts {

// What was derived from a set of part files, by file key, failures with their reason.
struct DerivedParts {
  GeometryCache geometry;
  std::unordered_map<std::string, std::unique_ptr<PartKnowledge>> known;
  std::unordered_map<std::string, std::string> failed;
};

// A model's own part blocks (a packed MPD's), flattened apart from the library's files, as they
// may differ from them. One per model: no model sees another's blocks.
class EmbeddedParts {
 public:
  explicit EmbeddedParts(const ldraw::Model& model);

 private:
  friend class PartLibrary;
  std::unordered_map<std::string, std::string> text_;  // "embedded:" key -> text
  DerivedParts derived_;
};

// Shared by the models checked at once: every call may come from any thread.
class PartLibrary {
 public:
  // `catalog` gives the measured masses and the brick family's exact shapes.
  PartLibrary(std::vector<std::filesystem::path> library_dirs, const BrickCatalog& catalog);

  // What a placed part is: from the catalog for its bricks and plates, else from its file
  // (embedded in its model, next to it or in a library). nullptr with `why` when there is no file
  // or it cannot be read. `embedded`: the part's model's blocks.
  const PartKnowledge* knowledge(const ldraw::PlacedPart& part, EmbeddedParts& embedded,
                                 std::string& why);

  const BrickCatalog& catalog() const { return catalog_; }
  double seconds() const;  // spent deriving, all models together

 private:
  const BrickCatalog& catalog_;
  // One lock for all that follows: derivation is a sixth of a corpus run, and most calls find
  // what they ask for at once.
  mutable std::mutex mutex_;
  LibraryFiles files_;
  DerivedParts from_files_;  // files from disk: the same whichever model places them
  std::unordered_map<std::string, std::unique_ptr<PartKnowledge>> catalog_parts_;
  double seconds_ = 0;

  const PartKnowledge* derive(const std::string& name, const PartFile& file, DerivedParts& derived,
                              const FileFinder& find, std::string& why);
};

}  // namespace lego::parts
