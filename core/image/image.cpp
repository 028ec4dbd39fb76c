#include "image/image.h"

#include <algorithm>
#include <cmath>
#include <fstream>

namespace whitted {

std::vector<uint8_t> toRgba8(const FrameBuffer& fb) {
  std::vector<uint8_t> out(fb.color.size() * 4);
  for (std::size_t i = 0; i < fb.color.size(); ++i)
    for (int c = 0; c < 4; ++c) {
      float v = fb.color[i][c];
      v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
      // lround of a float in [0, 255]: the sum in double is exact, so floor(x + 0.5) rounds half away from zero
      // as lround does, without its libm call
      out[i * 4 + c] = uint8_t(double(v * 255.0f) + 0.5);
    }
  return out;
}

uint32_t crc32(const uint8_t* data, std::size_t n, uint32_t crc) {
  static uint32_t table[256];
  static bool init = [] {
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      table[i] = c;
    }
    return true;
  }();
  (void)init;
  crc = ~crc;
  for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ data[i]) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

namespace {

void put32(std::vector<uint8_t>& v, uint32_t x) {
  for (int s = 24; s >= 0; s -= 8) v.push_back(uint8_t(x >> s));
}

void chunk(std::ofstream& f, const char* type, const std::vector<uint8_t>& data) {
  std::vector<uint8_t> buf;
  put32(buf, uint32_t(data.size()));
  buf.insert(buf.end(), type, type + 4);
  buf.insert(buf.end(), data.begin(), data.end());
  uint32_t crc = crc32(buf.data() + 4, buf.size() - 4);
  put32(buf, crc);
  f.write(reinterpret_cast<const char*>(buf.data()), std::streamsize(buf.size()));
}

}  // namespace

bool writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba) {
  if (width <= 0 || height <= 0 || rgba.size() < std::size_t(width) * height * 4) return false;
  std::ofstream f(path, std::ios::binary);
  if (!f) return false;
  const uint8_t sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
  f.write(reinterpret_cast<const char*>(sig), 8);

  std::vector<uint8_t> ihdr;
  put32(ihdr, uint32_t(width));
  put32(ihdr, uint32_t(height));
  ihdr.insert(ihdr.end(), {8, 6, 0, 0, 0});  // 8-bit RGBA, no interlace
  chunk(f, "IHDR", ihdr);

  // Raw scanlines (filter 0), top row first
  std::vector<uint8_t> raw;
  raw.reserve(std::size_t(height) * (width * 4 + 1));
  for (int y = height - 1; y >= 0; --y) {
    raw.push_back(0);
    const uint8_t* row = &rgba[std::size_t(y) * width * 4];
    raw.insert(raw.end(), row, row + std::size_t(width) * 4);
  }
  // zlib stream of stored (uncompressed) deflate blocks
  std::vector<uint8_t> z = {0x78, 0x01};
  std::size_t pos = 0;
  do {
    std::size_t len = std::min<std::size_t>(65535, raw.size() - pos);
    bool last = pos + len == raw.size();
    z.push_back(last ? 1 : 0);
    z.push_back(uint8_t(len & 0xFF));
    z.push_back(uint8_t(len >> 8));
    z.push_back(uint8_t(~len & 0xFF));
    z.push_back(uint8_t((~len >> 8) & 0xFF));
    z.insert(z.end(), raw.begin() + std::ptrdiff_t(pos), raw.begin() + std::ptrdiff_t(pos + len));
    pos += len;
  } while (pos < raw.size());
  // Adler-32, reduced modulo 65521 once per 5552 bytes (zlib's NMAX: the most bytes before b can overflow 32 bits)
  uint32_t a = 1, b = 0;
  for (std::size_t first = 0; first < raw.size(); first += 5552) {
    const std::size_t last = std::min(raw.size(), first + 5552);
    for (std::size_t k = first; k < last; ++k) {
      a += raw[k];
      b += a;
    }
    a %= 65521;
    b %= 65521;
  }
  put32(z, (b << 16) | a);
  chunk(f, "IDAT", z);
  chunk(f, "IEND", {});
  return bool(f);
}

}  // namespace whitted
