#pragma once
#include <sys/types.h>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/assembly.h"
#include "ldraw/color_table.h"
#include "ldraw/transform.h"

namespace lego::ldraw {

struct WriteOptions {
  std::string title = "Untitled";
  std::string name;  // `0 Name:`; defaults to the output file name
  std::string author = "legolization";
  bool steps = true;  // `0 STEP` between bricks of different Brick::source.step
};

// A type-1 line (ending in a newline): the part `reference` in `color` (a code, or a direct
// colour as 0x2RRGGBB) where `t` puts it.
std::string part_line(int color, const Transform& t, const std::string& reference);

// The LDraw transform of a brick of an assembly (origin at the top centre of its body).
Transform brick_transform(const Brick& brick, const std::array<int, 3>& origin_ldu);

// One .ldr: header, then one type-1 line per brick in the order given.
std::string to_ldr(const Assembly& assembly, const WriteOptions& options);

// One .mpd: a main model placing one submodel per build step (bricks grouped by
// Brick::source.step), each followed by `0 STEP`, so viewers show a step per submodel.
std::string to_mpd(const Assembly& assembly, const WriteOptions& options);

// The mode a new file (or folder) gets, as if made with open() (mkdir()) under the umask.
mode_t new_file_mode(bool folder);

// Writes text next to `path` first and renames it into place, so a failed write never leaves a
// partial file. Throws InputError when the path cannot be written.
void write_file_atomically(const std::filesystem::path& path, const std::string& text);
// Several files, all or none: each is written next to its path first, and only when every one
// is written are they renamed into place.
void write_files_atomically(
    const std::vector<std::pair<std::filesystem::path, std::string>>& files);

// A model in pieces: the first stands on the ground, each other one is built apart and set in
// place (a scene's object that does not reach the ground). In an .mpd each other piece is a
// submodel "<name>-piece-<k>.ldr" with its own build steps, placed in one step of the main model
// after the first piece's; in an .ldr its bricks follow as further steps, after a comment that
// says so. Bricks are where their assembly's origin puts them.
std::string to_ldr(const std::vector<const Assembly*>& pieces, const WriteOptions& options);
// The submodel name of a further piece: "model.mpd", 2 -> "model-piece-2.ldr".
std::string piece_submodel_name(const std::string& model_name, int piece);
std::string to_mpd(const std::vector<const Assembly*>& pieces, const WriteOptions& options);

// Whether `path` names an .mpd (any case).
bool is_mpd(const std::filesystem::path& path);
// to_ldr or to_mpd by the extension of `path`; the name defaults to its file name.
std::string model_text(const std::filesystem::path& path, const Assembly& assembly,
                       WriteOptions options);
std::string model_text(const std::filesystem::path& path,
                       const std::vector<const Assembly*>& pieces, WriteOptions options);
// model_text, written atomically.
void write_model(const std::filesystem::path& path, const Assembly& assembly, WriteOptions options);

}  // namespace lego::ldraw
