"""The driver half of the Whitted benchmark (whitted_bench, the C++ half, measures).

    runner.py    paths, the command runner (logs, provenance, CPU time of child processes), CSV files, the build
                 of whitted_bench, the generated meshes, the ParaView build
    config.py    what each section measures, full and quick (CI)
    sections/    one module per section: run(ctx) measures into CSV files, report(ctx, head) writes the
                 section's Markdown from those files (and adds headline rows), outputs(ctx) names what it promises
    plots.py     the PNG plots, drawn from the CSV files
    report.py    benchmark.md: provenance, headline table, the sections in order, file list
    cli.py       the command line (run_benchmark.py is its entry point)
"""
