// whitted_bench diff --image A.png --reference B.png: the image difference (image_metrics.h) of two PNG files of
// the same size, as JSON: rmse, psnr, ssim, max_levels (largest channel difference in 8-bit levels).
#include "bench_commands.h"
#include "image_metrics.h"

#include <cstdio>

namespace whitted::bench {

int cmdDiff(const Args& a) {
  FrameBuffer img, ref;
  std::string error;
  if (!readPng(a.str("image"), img, error) || !readPng(a.str("reference"), ref, error)) {
    std::fprintf(stderr, "whitted_bench diff: %s\n", error.c_str());
    return 2;
  }
  if (img.width != ref.width || img.height != ref.height) {
    std::fprintf(stderr, "whitted_bench diff: sizes differ (%dx%d vs %dx%d)\n", img.width, img.height, ref.width,
                 ref.height);
    return 2;
  }
  ImageError e = compareImages(img, ref);
  std::printf("{\"rmse\": %.6g, \"psnr\": %.6g, \"ssim\": %.6g, \"max_levels\": %d}\n", e.rmse, e.psnr, e.ssim,
              e.maxLevels);
  return 0;
}

}  // namespace whitted::bench
