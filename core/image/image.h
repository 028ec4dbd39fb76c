// Image output without external libraries: 8-bit conversion and a PNG writer (zlib "stored" blocks).
#pragma once

#include "image/renderer.h"

#include <cstdint>
#include <string>
#include <vector>

namespace whitted {

/// Clamps linear RGBA to [0,1] and quantises to 8 bits as an RGBA8 framebuffer does (round(c * 255)); rows stay
/// bottom to top. No gamma: VTK's non-PBR shading writes linear values to a non-sRGB framebuffer.
std::vector<uint8_t> toRgba8(const FrameBuffer& fb);

/// Writes an RGBA8 image whose rows are bottom to top as a PNG (top row first, as PNG stores it).
bool writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgbaBottomUp);

/// CRC-32 (PNG/zlib polynomial), exposed for tests.
uint32_t crc32(const uint8_t* data, std::size_t n, uint32_t crc = 0);

}  // namespace whitted
