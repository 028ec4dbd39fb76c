// Image output tests: the 8-bit conversion (clamping, rounding), PNG header, CRC and Adler-32.
#include "image/image.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using namespace whitted;

TEST(Image, PngRoundTripHeaderAndCrc) {
  const uint8_t ihdr[] = {'I', 'E', 'N', 'D'};
  EXPECT_EQ(crc32(ihdr, 4), 0xAE426082u);  // the well-known CRC of an empty IEND chunk
  FrameBuffer fb;
  fb.resize(3, 2);
  fb.color[0] = Color4(2.0f, -1.0f, std::nanf(""), 0.5f);
  auto px = toRgba8(fb);
  EXPECT_EQ(px[0], 255);
  EXPECT_EQ(px[1], 0);
  EXPECT_EQ(px[2], 0);
  EXPECT_EQ(px[3], 128);
  std::string path = ::testing::TempDir() + "/t.png";
  ASSERT_TRUE(writePng(path, 3, 2, px));
  FILE* f = std::fopen(path.c_str(), "rb");
  ASSERT_TRUE(f);
  unsigned char sig[8];
  ASSERT_EQ(std::fread(sig, 1, 8, f), 8u);
  std::fclose(f);
  EXPECT_EQ(sig[1], 'P');
  EXPECT_EQ(sig[2], 'N');
}

// The 8-bit conversion rounds as lround does, at and around every half level; the zlib stream's Adler-32 (summed
// with a deferred modulo) equals the per-byte definition on an image of several 5552-byte blocks.
TEST(Image, Rgba8RoundingAndPngAdler) {
  FrameBuffer fb;
  fb.resize(256, 40);  // 41 kB of scanlines: white rows (all bytes 255) would overflow a too-long modulo block
  for (int k = 0; k < 256; ++k) {
    const float half = (float(k) + 0.5f) / 255.0f;
    fb.color[std::size_t(k)] = Color4(half, std::nextafter(half, 0.0f), std::nextafter(half, 1.0f), float(k) / 255.0f);
  }
  for (std::size_t i = 256; i < fb.color.size(); ++i)
    fb.color[i] = i < 768
                      ? Color4(hashFloat(uint32_t(i), 1u), hashFloat(uint32_t(i), 2u), hashFloat(uint32_t(i), 3u), 1.0f)
                      : Color4(1.0f);
  const std::vector<uint8_t> px = toRgba8(fb);
  for (std::size_t i = 0; i < fb.color.size(); ++i)
    for (int c = 0; c < 4; ++c)
      ASSERT_EQ(px[4 * i + std::size_t(c)], uint8_t(std::lround(std::clamp(fb.color[i][c], 0.0f, 1.0f) * 255.0f)))
          << "pixel " << i << " channel " << c;

  std::string path = ::testing::TempDir() + "/adler.png";
  ASSERT_TRUE(writePng(path, fb.width, fb.height, px));
  FILE* f = std::fopen(path.c_str(), "rb");
  ASSERT_TRUE(f);
  std::vector<uint8_t> file;
  for (int ch; (ch = std::fgetc(f)) != EOF;) file.push_back(uint8_t(ch));
  std::fclose(f);
  // Scanlines as the PNG stores them (filter byte 0, top row first), and their Adler-32 byte by byte
  uint32_t a = 1, b = 0;
  for (int y = fb.height - 1; y >= 0; --y)
    for (int k = -1; k < fb.width * 4; ++k) {
      a = (a + (k < 0 ? 0u : px[std::size_t(y) * fb.width * 4 + std::size_t(k)])) % 65521;
      b = (b + a) % 65521;
    }
  // The zlib stream ends with the Adler-32, just before the IDAT chunk's CRC; IEND (12 bytes) follows
  ASSERT_GT(file.size(), 20u);
  const std::size_t end = file.size() - 12 - 4;
  const uint32_t stored = uint32_t(file[end - 4]) << 24 | uint32_t(file[end - 3]) << 16 | uint32_t(file[end - 2]) << 8 |
                          uint32_t(file[end - 1]);
  EXPECT_EQ(stored, (b << 16) | a);
}
