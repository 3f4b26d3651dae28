// An 8-bit RGBA image with rows top-down, and PNG files through libpng.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace colosim {

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  ///< width * height * 4 bytes, row 0 at the top

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgba(static_cast<size_t>(w) * h * 4, 0) {}
  uint8_t* at(int x, int y) { return &rgba[(static_cast<size_t>(y) * width + x) * 4]; }
  const uint8_t* at(int x, int y) const { return &rgba[(static_cast<size_t>(y) * width + x) * 4]; }
};

/// Writes an RGBA PNG. Writes to a temporary file beside `path` and renames it, so a
/// failed write never leaves a truncated file. Throws std::runtime_error naming the path.
void writePng(const std::string& path, const Image& image);

/// Reads any PNG as 8-bit RGBA. Throws std::runtime_error naming the path when the file
/// is missing or not a valid PNG.
Image readPng(const std::string& path);

}  // namespace colosim
