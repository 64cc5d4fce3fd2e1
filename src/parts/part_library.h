#pragma once
// Part knowledge, derived once per part file and cached for the process (PHYSICS.md "Parts").
#include <filesystem>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/brick_catalog.h"
#include "ldraw/reader.h"
#include "parts/derive.h"
#include "parts/part_files.h"
#include "parts/part_geometry.h"

namespace lego::parts {

class PartLibrary {
 public:
  // `catalog` gives the measured masses and the brick family's exact shapes.
  PartLibrary(std::vector<std::filesystem::path> library_dirs, const BrickCatalog& catalog);

  // What a placed part of `model` is: from the catalog for its bricks and plates, else from its
  // file (embedded in the model, next to it or in a library). nullptr with `why` when there is no
  // file or it cannot be read.
  const PartKnowledge* knowledge(const ldraw::PlacedPart& part, const ldraw::Model& model,
                                 std::string& why);

  const BrickCatalog& catalog() const { return catalog_; }
  double seconds() const { return seconds_; }  // spent deriving, all models together

 private:
  const BrickCatalog& catalog_;
  LibraryFiles files_;
  GeometryCache geometry_;  // files from disk: the same whichever model places them
  std::unordered_map<std::string, std::unique_ptr<PartKnowledge>> known_;  // by file key
  std::unordered_map<std::string, std::string> failed_;                    // file key -> why
  std::unordered_map<std::string, std::unique_ptr<PartKnowledge>> catalog_parts_;
  // A packed MPD's own blocks: flattened apart, as they may differ from the library's.
  const ldraw::Model* embedding_model_ = nullptr;
  std::unique_ptr<GeometryCache> embedded_geometry_;
  std::unordered_map<std::string, std::unique_ptr<PartKnowledge>> embedded_known_;
  std::unordered_map<std::string, std::string> embedded_text_;  // key -> text
  double seconds_ = 0;

  const PartKnowledge* derive(
      const std::string& name, const PartFile& file, GeometryCache& cache, const FileFinder& find,
      std::unordered_map<std::string, std::unique_ptr<PartKnowledge>>& known, std::string& why);
};

}  // namespace lego::parts
