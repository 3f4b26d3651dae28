// A tiny 5 x 7 bitmap font for on-screen numbers and short words (pure data, no GL).
#pragma once

#include <string>
#include <vector>

namespace colosim {

/// The 7 rows of a glyph, 5 bits each (bit 4 = leftmost column); nullptr when the
/// character has no glyph. Lower-case letters map to upper case.
const unsigned char* glyphRows(char c);

/// Triangles (x, y pairs in pixels, y down) covering the lit font pixels of `text`, its
/// top-left corner at (x_px, y_px), each font pixel scale x scale pixels, 6 px advance
/// per character at scale 1; '\n' starts a new line. Characters without a glyph are
/// drawn as blanks.
std::vector<float> textTriangles(const std::string& text, int x_px, int y_px, int scale);

}  // namespace colosim
