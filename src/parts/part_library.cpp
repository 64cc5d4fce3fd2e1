#include "parts/part_library.h"

#include <fmt/format.h>

#include <chrono>

#include "core/lattice.h"
#include "core/stopwatch.h"

namespace lego::parts {
namespace {

std::string base_name(const std::string& name) {
  const auto slash = name.rfind('/');
  return slash == std::string::npos ? name : name.substr(slash + 1);
}

}  // namespace

EmbeddedParts::EmbeddedParts(const ldraw::Model& model) {
  for (const auto& [block, text] : model.embedded_parts)
    text_.emplace("embedded:" + safe_reference(block), text);
}

PartLibrary::PartLibrary(std::vector<std::filesystem::path> library_dirs,
                         const BrickCatalog& catalog)
    : catalog_(catalog), files_(std::move(library_dirs)) {}

double PartLibrary::seconds() const {
  const std::lock_guard lock(mutex_);
  return seconds_;
}

const PartKnowledge* PartLibrary::derive(const std::string& name, const PartFile& file,
                                         DerivedParts& derived, const FileFinder& find,
                                         std::string& why) {
  if (auto it = derived.known.find(file.key); it != derived.known.end()) return it->second.get();
  if (auto it = derived.failed.find(file.key); it != derived.failed.end()) {
    why = it->second;
    return nullptr;
  }
  const auto start = std::chrono::steady_clock::now();
  auto geometry = derived.geometry.flatten(file, find, why);
  const PartKnowledge* out = nullptr;
  if (geometry) {
    // A part larger than any made (the largest baseplates are 48 studs across) would make the
    // contact search walk its area cell by cell: 1e6 LDU across is 1e10 cells.
    const double extent = geometry_extent(*geometry);
    if (extent > kMaxPartExtentLdu) {
      why = fmt::format("its file draws it {:.3g} studs across, more than the {:.0f} a part may be",
                        extent / kLduPerStud, kMaxPartExtentLdu / kLduPerStud);
      geometry = nullptr;
    }
  }
  if (!geometry) {
    derived.failed[file.key] = why;
  } else {
    auto k = std::make_unique<PartKnowledge>(derive_part(name, *geometry, catalog_));
    out = k.get();
    derived.known.emplace(file.key, std::move(k));
  }
  seconds_ += seconds_since(start);
  return out;
}

const PartKnowledge* PartLibrary::knowledge(const ldraw::PlacedPart& p, EmbeddedParts& embedded,
                                            std::string& why) {
  const std::lock_guard lock(mutex_);
  if (const BrickType* t = catalog_.find(p.part)) {
    auto& k = catalog_parts_[t->part];
    if (!k) {
      k = std::make_unique<PartKnowledge>();
      k->type = *t;
    }
    return k.get();
  }
  const FileFinder from_library = [this](std::string_view reference, std::string& w) {
    return files_.find(reference, w);
  };
  if (!p.embedded_definition.empty() || !embedded.text_.empty()) {
    const FileFinder embedded_first = [&embedded, &from_library](std::string_view reference,
                                                                 std::string& w) {
      const std::string name = safe_reference(reference);
      for (const std::string& key :
           {"embedded:" + name, "embedded:parts/" + name, "embedded:p/" + name}) {
        auto it = embedded.text_.find(key);
        if (it != embedded.text_.end()) return std::optional<PartFile>(PartFile{key, &it->second});
      }
      // Packed files name blocks by their path ("parts/s/3001s01.dat") or bare.
      for (auto& [key, text] : embedded.text_)
        if (base_name(key) == base_name(name)) return std::optional<PartFile>(PartFile{key, &text});
      return from_library(reference, w);
    };
    std::optional<PartFile> file;
    if (!p.embedded_definition.empty())
      file = embedded_first(p.embedded_definition, why);
    else if (!p.definition.empty())
      file = files_.read(p.definition, why);
    if (!file) {
      why =
          "no part file for it (not in the model, beside it or in the LDraw library; see "
          "--ldraw-dir)";
      return nullptr;
    }
    return derive(p.part, *file, embedded.derived_, embedded_first, why);
  }
  if (p.definition.empty()) {
    why =
        "no part file for it (not in the model, beside it or in the LDraw library; see "
        "--ldraw-dir)";
    return nullptr;
  }
  auto file = files_.read(p.definition, why);
  if (!file) return nullptr;
  return derive(p.part, *file, from_files_, from_library, why);
}

}  // namespace lego::parts
