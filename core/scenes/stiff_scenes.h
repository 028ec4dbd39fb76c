// Stiff scenes for the error estimate: where the depth cap and the contribution threshold leave out the most
// (many bounces between mirrors, glass inside glass, a light whose shadow rays cross several glass walls). Used by
// the truncation-bound tests and the benchmark's calibration of the error estimate.
#pragma once

#include "scenes/scenes.h"

namespace whitted {

/// Axis-aligned box mesh with outward-facing triangles.
TriangleMesh makeBoxMesh(const Vec3& lo, const Vec3& hi);

/// An omnidirectional point light at p (white, intensity 1, no distance attenuation).
Light makePointLight(const Vec3& p);

/// Two facing mirrors (kr 0.9, a little grey diffuse) 1 apart and 40 long, a red sphere between them, a back wall
/// and one point light; the camera looks down the corridor at an angle, so rays bounce up to ~20 times.
void buildFacingMirrorsScene(Scene& scene, CameraSpec& cam);

/// A glass sphere (kt 0.9, kr 0.1, IOR 1.5, opacity 0.05) holding a second one (kt 0.8, kr 0.2, IOR 1.33) holding
/// an opaque orange ball, over a floor, one point light. kr + kt = 1 with a local colour: the series diverges, so
/// the truncation bound is stated against IntegratorSettings::truncationReferenceDepth.
void buildNestedGlassScene(Scene& scene, CameraSpec& cam);

/// A point light inside two nested glass boxes (kt 0.35 each, kr 0.1) over a floor: shadow rays toward it cross
/// two walls (transmittance 0.1225), so a threshold above that cuts the light they carry.
void buildLightInGlassScene(Scene& scene, CameraSpec& cam);

/// The error estimate's study scene (issue 28): a mirror floor (kr 0.5), a glass sphere (IOR 1.5), a fence of
/// 24 thin posts (0.02 wide: under a pixel at 160 x 120, so sampling error dominates there), a cube, two point
/// lights (the second at half intensity).
void buildFenceScene(Scene& scene, CameraSpec& cam);

/// Text-like fine detail (issue 28): a white page under one light with 8 rows of 16 seven-segment glyphs whose
/// strokes are 0.0075 wide (about a third of a pixel at 160 x 120), seen slightly obliquely so that the strokes do
/// not line up with the pixel grid: aliasing dominates the error.
void buildTextScene(Scene& scene, CameraSpec& cam);

}  // namespace whitted
