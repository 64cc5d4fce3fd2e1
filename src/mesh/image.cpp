#include "mesh/image.h"

#define STB_IMAGE_IMPLEMENTATION
#define STBI_FAILURE_USERMSG
#include <stb_image.h>

namespace lego::mesh {
namespace {

bool take(unsigned char* pixels, int w, int h, Texture& out, std::string& why) {
  if (!pixels) {
    why = stbi_failure_reason();
    return false;
  }
  out.width = w;
  out.height = h;
  out.rgb.assign(pixels, pixels + size_t(w) * h * 3);
  stbi_image_free(pixels);
  return true;
}

}  // namespace

bool load_image(const std::filesystem::path& path, Texture& out, std::string& why) {
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load(path.c_str(), &w, &h, &channels, 3);  // before w and h are read
  return take(pixels, w, h, out, why);
}

bool decode_image(const unsigned char* data, size_t size, Texture& out, std::string& why) {
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load_from_memory(data, int(size), &w, &h, &channels, 3);
  return take(pixels, w, h, out, why);
}

}  // namespace lego::mesh
