// Human-readable frame report (the same text the CLI and vtkWhittedPass print).
#pragma once

#include "image/renderer.h"
#include "scene/scene.h"

#include <string>

namespace whitted {

/// Formats one frame's statistics: time per phase, rays by kind and saved, scene size, BVH memory, and the
/// frame's error estimate next to its run time.
std::string frameReport(const FrameStats& frame, const SceneStats& scene, const CommitStats& commit, int width,
                        int height, double secondsOther = 0.0, const char* otherLabel = nullptr);

}  // namespace whitted
