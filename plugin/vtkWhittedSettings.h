/**
 * @file    vtkWhittedSettings.h
 * @brief   the one table of the ray tracer's user settings: name, owner, default, range, meaning
 *
 * Every setting a user sets on vtkWhittedPass, or on ParaView's Whitted Ray Trace view
 * (vtkPVWhittedView, xml/WhittedView.xml), is one row of VTK_WHITTED_SETTINGS below. A new setting
 * is a row here, a property in the XML and a row in plugin/README.md, plus what it does.
 * Generated from the table (macros below; VTK's Python and ParaView's client-server wrappers expand
 * macros when they parse a header, so they see every generated setter):
 * - vtkWhittedPass: the members at their defaults, Set (clamped to the range) / Get / On / Off,
 *   PrintSelf.
 * - vtkPVWhittedView: the one-line forwarders of the pass's settings; for its own settings the
 *   members, getters, clamped setters of numbers, PrintSelf.
 * Checked against the table (stated by hand, or generated and worth proving; a test fails when they
 * disagree):
 * - testing/settings/check_settings.py, in both builds (vtk.settings.Sources,
 *   paraview.settings.sources): the XML's properties (label, command, default_values, range
 *   domain, Documentation: the GUI's tooltips, property group), the view's and the pass's
 *   generated accessors, the Python-wrapped pass (VTK build), the settings tables of
 *   plugin/README.md.
 * - TestWhittedSettings (VTK build): the pass's defaults and clamps.
 * - paraview.settings (ParaView build): the view's defaults, clamps and forwarding to the pass, and
 *   the XML as ParaView's server manager reads it.
 *
 * Columns: X(owner, type, name, default, minimum, maximum, documentation)
 * - owner: Pass, a vtkWhittedPass setting (the ParaView view forwards it in one line), or View, a
 *   setting of the ParaView view alone (how it picks interactive frames, parallel replication).
 * - documentation: what the setting means to a user, word for word the XML's Documentation.
 * Booleans have the range false..true.
 */

#ifndef vtkWhittedSettings_h
#define vtkWhittedSettings_h

// clang-format off
#define VTK_WHITTED_SETTINGS(X)                                                                    \
  X(Pass, int, MaxDepth, 5, 0, 64,                                                                 \
    "Maximum number of secondary bounces (reflection and refraction) per camera ray; 0 gives "     \
    "local shading and shadows only.")                                                             \
  X(Pass, int, SamplesPerPixel, 1, 1, 64,                                                          \
    "Camera rays per pixel (stratified, jittered) for anti-aliasing; 1 traces the pixel centre, "  \
    "like OpenGL without multisampling. The cost grows linearly. Interactive frames use 1.")       \
  X(Pass, bool, AdaptiveSampling, false, false, true,                                              \
    "Trace one sample per pixel first and the full Samples Per Pixel only where the neighbouring " \
    "pixels do not predict a pixel (edges, shadow boundaries, highlights, reflections; smooth "    \
    "shading is left alone). No effect with 1 sample per pixel.")                                  \
  X(Pass, bool, Shadows, true, false, true,                                                        \
    "Trace a shadow ray toward every light. Transmissive objects cast coloured, lighter "          \
    "shadows.")                                                                                    \
  X(Pass, bool, ShadowsFromBrightestLightOnly, false, false, true,                                  \
    "Trace shadow rays toward the brightest light only (intensity times its brightest colour "     \
    "channel; the first of equals); the other lights shade without shadows. With ParaView's "      \
    "light kit this is the key light: the fill, head and back lights, a third as bright or less, " \
    "would add faint second shadows at up to four times the shadow rays. On by default in the "    \
    "ParaView view, off for vtkWhittedPass (every light whose Shadow Attenuation is above 0 casts " \
    "shadows).")                                                                                   \
  X(Pass, bool, Reflections, true, false, true,                                                    \
    "Trace mirror rays for objects with a Reflectance above 0.")                                   \
  X(Pass, bool, Refractions, true, false, true,                                                    \
    "Bend transmitted rays by the objects' Index Of Refraction (Snell's law, total internal "      \
    "reflection). Off: transmissive objects are see-through without bending.")                     \
  X(Pass, bool, Fresnel, false, false, true,                                                       \
    "Exact (unpolarised) dielectric Fresnel at refracting surfaces: transmissive objects reflect " \
    "more at grazing angles (part of the transmittance moves to the reflectance).")                \
  X(Pass, double, ContributionThreshold, 1.0 / 255.0, 0.0, 1.0,                                    \
    "A secondary ray whose weight (the product of the reflectances and transmittances along its "  \
    "path) is below this value is not traced. The default, 1/255, can change a pixel by less "     \
    "than one 8-bit step; larger values are faster and darken deep reflections.")                  \
  X(Pass, double, TargetError, 0.0, 0.0, 1.0,                                                      \
    "Still frames: refine where the estimated error is largest (more samples, or a deeper Max "     \
    "Depth and lower Contribution Threshold where the truncation bound dominates) until the "      \
    "frame's estimated error (RMS over pixels of the truncation bound plus the sampling "           \
    "estimate, in colour units 0..1) is at most this value; 0 = no target. Interactive frames are " \
    "never refined.")                                                                              \
  X(Pass, double, TimeBudget, 0.0, 0.0, 3600.0,                                                    \
    "Still frames: refine progressively (as for Target Error) for at most this many seconds, "     \
    "stopping early when Target Error is met; 0 = no budget. The seconds are those spent "         \
    "rendering the frame: with Progressive Display all its renders together (as ray-traced "       \
    "samples accumulate over renders until the camera, the data or a setting changes, which "      \
    "starts the frame and its budget over); time between renders does not count. The first "       \
    "pass always completes; refinement stops within one tile's time of the budget. The error "     \
    "annotation shows the seconds spent of the budget.")                                           \
  X(Pass, bool, ShowErrorImage, false, false, true,                                               \
    "Show the per-pixel estimated error (truncation bound plus sampling estimate, as in Target "   \
    "Error) as grey levels instead of the rendering: grey = Error Image Scale x error, so white "   \
    "marks pixels whose error is 1 / Error Image Scale or more.")                                  \
  X(Pass, double, ErrorImageScale, 10.0, 1.0, 1000.0,                                             \
    "Brightness of the error image (Show Error Image): grey level per unit of estimated error.")   \
  X(Pass, int, NumberOfThreads, 0, 0, 1024,                                                        \
    "Tracing threads per rendering process; 0 uses every core the process may run on (its CPU "    \
    "affinity: mpirun binds each rank to one core by default, so start pvserver or pvbatch with "  \
    "mpirun --bind-to none, or give each rank several cores with --map-by ppr:1:node:pe=N, to "    \
    "trace with N threads per rank).")                                                             \
  X(Pass, int, TimeCacheMemory, 100, 0, 1048576,                                                   \
    "Megabytes of memory for keeping the converted geometry and BVHs of earlier time steps (or "   \
    "earlier inputs of the same object shown again), so that showing them again, e.g. replaying "  \
    "an animation, converts and builds nothing; new inputs that are not time steps (a contour "    \
    "slider dragged) are not kept. Least recently used first out; never fills the last tenth of "  \
    "the machine's memory; 0 = off. Default 100, as ParaView's animation geometry cache.")         \
  X(Pass, int, InteractiveMaxDepth, 1, 0, 64,                                                      \
    "Maximum bounces while the camera moves (the smaller of this and Max Depth).")                 \
  X(Pass, bool, InteractiveShadows, true, false, true,                                             \
    "Trace shadow rays while the camera moves (when Shadows is on).")                              \
  X(View, double, InteractiveFrameTime, 0.1, 0.005, 2.0,                                           \
    "Target wall-clock seconds of a frame while the camera moves. The view lowers the traced "     \
    "resolution (up to Maximum Image Reduction) until frames take about this long; the "           \
    "full-quality frame follows when interaction stops.")                                          \
  X(View, int, MaximumImageReduction, 8, 1, 16,                                                    \
    "Largest factor by which the width and height of frames traced while the camera moves are "    \
    "reduced. 1 disables reduced-resolution interaction.")                                         \
  X(View, bool, ProgressiveDisplay, true, false, true,                                             \
    "Still frames with Target Error or Time Budget are shown as they refine: each frame runs "      \
    "Refinement Rounds Per Render rounds (1 in the GUI) and the view renders again until the "      \
    "target is met or the budget spent; any interaction interrupts it at once. Off, or in a "       \
    "script with Refinement Rounds Per Render 0: each still render refines the frame fully.")       \
  X(View, int, RefinementRoundsPerRender, 0, 0, 64,                                                \
    "Progressive Display: refinement rounds per still render; 0 = 1 in the GUI (which renders "     \
    "again by itself) and all of them in scripts. A script that sets it renders again while "       \
    "Refinement Unfinished is 1.")                                                                 \
  X(View, bool, ShowErrorAnnotation, false, false, true,                                           \
    "Show the last still frame's tracing time, samples per pixel, estimated error (RMS) and "       \
    "whether Target Error was met in the view's lower left corner.")                               \
  X(View, bool, ReplicateGeometry, true, false, true,                                              \
    "Parallel rendering only (mpirun pvbatch or pvserver): give every rank a copy of all "         \
    "rendered geometry so shadows, reflections and refractions see the whole scene, and split "    \
    "the image between ranks. Costs one copy of the geometry per rank. Off: each rank traces "     \
    "only its own data and secondary rays miss the other ranks' geometry.")
// clang-format on

// Pass settings whose default in ParaView's Whitted view differs from vtkWhittedPass's, as
// X(name, view default): the view sets them when it is made, its XML default_values say the same
// (checked by testing/settings/check_settings.py and testing/paraview/test_settings.py).
// - ShadowsFromBrightestLightOnly: ParaView always lights with its light kit (five lights, the key
//   light three times the others), and its Render View draws no shadows; one key-light shadow is
//   what a ParaView user expects to gain, at a third of the shadow rays (benchmark `paraview`
//   section: both policies).
// clang-format off
#define VTK_WHITTED_VIEW_DEFAULTS(X)                                                               \
  X(ShadowsFromBrightestLightOnly, true)
// clang-format on

/// One row of the table, as a constant: vtkWhittedSettings::<name>.Default and so on.
template <typename T>
struct vtkWhittedSetting
{
  const char* Name;
  T Default;
  T Minimum;
  T Maximum;
  const char* Documentation;
};

namespace vtkWhittedSettings
{
#define VTK_WHITTED_SETTING_CONSTANT(owner, type, name, def, min, max, doc)                        \
  constexpr vtkWhittedSetting<type> name{ #name, def, min, max, doc };
VTK_WHITTED_SETTINGS(VTK_WHITTED_SETTING_CONSTANT)
#undef VTK_WHITTED_SETTING_CONSTANT
}

// Building blocks of what the classes generate from the table (each class selects its rows by
// owner, e.g. VTK_WHITTED_PASS_ACCESSORS in vtkWhittedPass.h).
// A setting's accessors in VTK style: SetX (numbers clamped to the table's range, reported by
// GetXMinValue and GetXMaxValue) and GetX; booleans also XOn and XOff.
#define VTK_WHITTED_SETTING_ACCESSORS_bool(name)                                                   \
  vtkSetMacro(name, bool);                                                                         \
  vtkGetMacro(name, bool);                                                                         \
  vtkBooleanMacro(name, bool);
#define VTK_WHITTED_SETTING_ACCESSORS_int(name) VTK_WHITTED_SETTING_CLAMPED(int, name)
#define VTK_WHITTED_SETTING_ACCESSORS_double(name) VTK_WHITTED_SETTING_CLAMPED(double, name)
#define VTK_WHITTED_SETTING_CLAMPED(type, name)                                                    \
  vtkSetClampMacro(                                                                                \
    name, type, vtkWhittedSettings::name.Minimum, vtkWhittedSettings::name.Maximum);               \
  vtkGetMacro(name, type);
// A setting's data member, at the table's default
#define VTK_WHITTED_SETTING_MEMBER(type, name) type name = vtkWhittedSettings::name.Default;
// A setting's line of PrintSelf(ostream& os, vtkIndent indent)
#define VTK_WHITTED_SETTING_PRINT(name) os << indent << #name ": " << this->name << "\n";

#endif
// VTK-HeaderTest-Exclude: vtkWhittedSettings.h
