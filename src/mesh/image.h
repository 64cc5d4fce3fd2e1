#pragma once
// Image decoding for textures (stb_image: PNG, JPEG, BMP, TGA...).
#include <cstddef>
#include <filesystem>
#include <string>

#include "mesh/mesh.h"

namespace lego::mesh {

bool load_image(const std::filesystem::path& path, Texture& out, std::string& why);
bool decode_image(const unsigned char* data, size_t size, Texture& out, std::string& why);

}  // namespace lego::mesh
