"""What each section measures. The quick mode exercises every code path on tiny inputs (CI, well under a minute
of measuring on 2 cores); the full mode is what the report in data/benchmark/results comes from."""

DEFAULT_LABEL = "spp 1, depth 5, threshold 1/255, non-adaptive"


def config(quick):
    if quick:
        return dict(
            quick=True,
            ray_scenes=["classic", "iso60k"], ray_size="96x72", ray_reps=2,
            build_scenes=["iso60k"], build_reps=1,
            pov_sizes=["160x120"], pov_reps=1, frame_reps=2,
            vtk_scene="iso60k", vtk_size="256x256", vtk_reps=2, vtk_first_runs=1, vtk_pairs=[(0, 1), (8, 8)],
            glyph_counts=[1000], glyph_size="160x120", glyph_reps=1,
            vol_dims=32, vol_size="160x120", vol_reps=1,
            vol_step_scene="wavelet64", vol_step_size="64x48", vol_steps="2,1,0.5", vol_reference_step=0.125,
            scaling_tri=["iso60k"], scaling_size_scene="classic", scaling_sizes=["64x48", "128x96"],
            scaling_thread_scenes=["classic"], scaling_thread_size="128x96",
            update_scene="iso60k", update_size="96x72", update_reps=1,
            error_scenes=["classic"], error_size="64x48", error_ref_spp=4, error_ref_depth=8, error_reps=1,
            error_budget=1.0, meshes=[],
            mpi_extent=10, mpi_size="160x120", mpi_frames=1, mpi_reps=1,
            pv_extent=10, pv_size="160x120", pv_still=2, pv_changes=1, pv_reps=1,
            ts_extent=10, ts_size="160x120", ts_steps=3, ts_reps=1)
    return dict(
        quick=False,
        ray_scenes=["classic", "iso60k", "iso1m", "iso4m", "points100k", "tubes", "glassmirror"],
        ray_size="1024x768", ray_reps=5,
        build_scenes=["iso60k", "iso1m", "iso4m", "points100k", "tubes"], build_reps=3,
        pov_sizes=["1024x768", "2048x1536"], pov_reps=5, frame_reps=5,
        # (VTK MultiSamples, our samples per pixel) compared with each other: no antialiasing against 1 sample,
        # MSAA 8 against 8 samples (MSAA shades once per pixel, so 8 spp does more work for its edges)
        # vtk_first_runs: more fresh processes per configuration, alternating, that time only a first frame (one
        # process's first frame swings with its page faults and Mesa's shader cache; the report takes the median)
        vtk_scene="iso1m", vtk_size="1024x1024", vtk_reps=10, vtk_first_runs=4, vtk_pairs=[(0, 1), (8, 8)],
        glyph_counts=[10000, 100000, 1000000], glyph_size="1024x768", glyph_reps=3,
        vol_dims=256, vol_size="1024x768", vol_reps=5,
        vol_step_scene="wavelet256", vol_step_size="512x384", vol_steps="4,2,1,0.5,0.25",
        vol_reference_step=0.0625,
        scaling_tri=["iso60k", "iso1m", "iso4m"], scaling_size_scene="iso1m",
        scaling_sizes=["256x192", "512x384", "1024x768", "2048x1536"],
        scaling_thread_scenes=["classic", "iso1m", "tubes"], scaling_thread_size="1024x768",
        update_scene="iso1m", update_size="1024x768", update_reps=5,
        error_scenes=["classic", "iso1m", "points100k", "tubes", "glassmirror", "mirrors", "nestedglass",
                      "lightinglass"], error_size="192x144",
        error_ref_spp=64, error_ref_depth=16, error_reps=3, error_budget=1.5, meshes=["1m", "4m"],
        mpi_extent=122, mpi_size="1024x768", mpi_frames=3, mpi_reps=3,
        pv_extent=122, pv_size="1024x768", pv_still=5, pv_changes=3, pv_reps=3,
        ts_extent=122, ts_size="1024x768", ts_steps=5, ts_reps=2)
