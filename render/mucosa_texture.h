// The procedural mucosa texture, made at start-up (no binary asset): a pink wall with
// soft mottling and branching submucosal vessels. Tileable in both directions (u runs
// around the colon and must meet itself at the seam; v repeats along). The glossy wet
// look is the renderer's specular highlight, not part of the texture.
#pragma once

#include <cstdint>

#include "render/image.h"

namespace colosim {

struct MucosaOptions {
  int size_px = 512;         ///< the texture is size x size pixels
  int vessel_count = 9;      ///< root vessels; each branches
  uint32_t seed = 20260217;  ///< std::mt19937 seed: same seed, same bytes
};

/// Builds the texture (alpha = 255). Deterministic for a given options.
Image makeMucosaTexture(const MucosaOptions& options = {});

}  // namespace colosim
