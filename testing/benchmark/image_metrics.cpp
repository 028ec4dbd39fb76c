#include "image_metrics.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace whitted::bench {

namespace {

float clamp01(float x) {
  return std::isfinite(x) ? std::clamp(x, 0.0f, 1.0f) : 0.0f;
}

/// Separable Gaussian blur (11 taps, sigma 1.5) keeping only the fully covered ("valid") region.
std::vector<double> blurValid(const std::vector<double>& in, int w, int h, int& ow, int& oh) {
  const int r = 5;
  double k[2 * r + 1], sum = 0.0;
  for (int i = -r; i <= r; ++i) sum += k[i + r] = std::exp(-0.5 * i * i / (1.5 * 1.5));
  for (double& v : k) v /= sum;
  ow = w - 2 * r;
  oh = h - 2 * r;
  if (ow <= 0 || oh <= 0) return {};
  std::vector<double> tmp(std::size_t(ow) * h), out(std::size_t(ow) * oh);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < ow; ++x) {
      double s = 0.0;
      for (int i = 0; i <= 2 * r; ++i) s += k[i] * in[std::size_t(y) * w + x + i];
      tmp[std::size_t(y) * ow + x] = s;
    }
  for (int y = 0; y < oh; ++y)
    for (int x = 0; x < ow; ++x) {
      double s = 0.0;
      for (int i = 0; i <= 2 * r; ++i) s += k[i] * tmp[std::size_t(y + i) * ow + x];
      out[std::size_t(y) * ow + x] = s;
    }
  return out;
}

double ssimChannel(const std::vector<double>& a, const std::vector<double>& b, int w, int h) {
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;  // dynamic range 1
  std::size_t n = a.size();
  std::vector<double> aa(n), bb(n), ab(n);
  for (std::size_t i = 0; i < n; ++i) {
    aa[i] = a[i] * a[i];
    bb[i] = b[i] * b[i];
    ab[i] = a[i] * b[i];
  }
  int ow, oh;
  auto ma = blurValid(a, w, h, ow, oh), mb = blurValid(b, w, h, ow, oh);
  auto saa = blurValid(aa, w, h, ow, oh), sbb = blurValid(bb, w, h, ow, oh), sab = blurValid(ab, w, h, ow, oh);
  if (ma.empty()) return 1.0;
  double sum = 0.0;
  for (std::size_t i = 0; i < ma.size(); ++i) {
    double va = saa[i] - ma[i] * ma[i], vb = sbb[i] - mb[i] * mb[i], cov = sab[i] - ma[i] * mb[i];
    sum += ((2.0 * ma[i] * mb[i] + c1) * (2.0 * cov + c2)) / ((ma[i] * ma[i] + mb[i] * mb[i] + c1) * (va + vb + c2));
  }
  return sum / double(ma.size());
}

}  // namespace

float maxChannelDifference(const Color4& a, const Color4& b) {
  float m = 0.0f;
  for (int c = 0; c < 3; ++c) m = std::max(m, std::abs(float(clamp01(a[c])) - float(clamp01(b[c]))));
  return m;
}

ImageError compareImages(const FrameBuffer& img, const FrameBuffer& ref) {
  ImageError e;
  std::size_t n = std::min(img.color.size(), ref.color.size());
  if (n == 0) return e;
  double sum2 = 0.0, mc2 = 0.0, mcMax = 0.0;
  std::vector<double> ca[3], cb[3];
  for (int c = 0; c < 3; ++c) {
    ca[c].resize(n);
    cb[c].resize(n);
  }
  for (std::size_t i = 0; i < n; ++i) {
    double m = 0.0;
    for (int c = 0; c < 3; ++c) {
      double a = clamp01(img.color[i][c]), b = clamp01(ref.color[i][c]);
      ca[c][i] = a;
      cb[c][i] = b;
      sum2 += (a - b) * (a - b);
      m = std::max(m, std::abs(a - b));
    }
    mc2 += m * m;
    mcMax = std::max(mcMax, m);
  }
  e.rmse = std::sqrt(sum2 / (3.0 * double(n)));
  e.psnr = e.rmse > 1e-5 ? 20.0 * std::log10(1.0 / e.rmse) : 100.0;
  e.maxChannelRms = std::sqrt(mc2 / double(n));
  e.maxChannelMax = mcMax;
  e.maxLevels = int(std::lround(255.0 * mcMax));
  double s = 0.0;
  for (int c = 0; c < 3; ++c) s += ssimChannel(ca[c], cb[c], img.width, img.height);
  e.ssim = s / 3.0;
  return e;
}

bool readPng(const std::string& path, FrameBuffer& fb, std::string& error) {
  // libpng's low-level API: stored sample values as they are (the simplified API would apply the file's gAMA
  // chunk, and POV-Ray marks its linear output with gamma 1.0)
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) {
    error = "cannot open " + path;
    return false;
  }
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  std::vector<uint8_t> rgba;
  std::vector<png_bytep> rowPointers;
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(f);
    error = path + " is not a readable PNG file";
    return false;
  }
  png_init_io(png, f);
  png_read_info(png, info);
  // Any colour type and depth to 8-bit RGBA
  png_set_expand(png);
  png_set_strip_16(png);
  png_set_gray_to_rgb(png);
  png_set_add_alpha(png, 0xff, PNG_FILLER_AFTER);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  const int w = int(png_get_image_width(png, info)), h = int(png_get_image_height(png, info));
  rgba.resize(std::size_t(w) * h * 4);
  for (int y = 0; y < h; ++y) rowPointers.push_back(&rgba[std::size_t(y) * w * 4]);
  png_read_image(png, rowPointers.data());
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(f);
  fb.resize(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint8_t* p = &rgba[(std::size_t(h - 1 - y) * w + x) * 4];  // PNG rows are top to bottom
      fb.color[std::size_t(y) * w + x] = Color4(p[0], p[1], p[2], p[3]) / 255.0f;
    }
  return true;
}

bool readColorCache(const std::string& path, int w, int h, FrameBuffer& fb) {
  if (path.empty()) return false;
  FILE* fp = std::fopen(path.c_str(), "rb");
  if (!fp) return false;
  fb.resize(w, h);
  const bool whole = std::fread(fb.color.data(), sizeof(Color4), fb.color.size(), fp) == fb.color.size();
  std::fclose(fp);
  return whole;
}

void writeColorCache(const std::string& path, const FrameBuffer& fb) {
  if (path.empty()) return;
  if (FILE* fp = std::fopen(path.c_str(), "wb")) {
    std::fwrite(fb.color.data(), sizeof(Color4), fb.color.size(), fp);
    std::fclose(fp);
  }
}

}  // namespace whitted::bench
