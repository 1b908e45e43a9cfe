#!/usr/bin/env python3
"""The soak's table (docs/performance.md, "Every built-in scene"), from bench/soak.sh's results.

    bench/soak_table.py [RESULTS_DIR]

Reads RESULTS_DIR/soak-<run>.csv (default bench/results), the samples clothsim_soak wrote, and
the verdict beside each (soak-<run>.txt), and prints one Markdown row per run: the simulated and
CPU time, the CPU time per simulated second (the mean, and the most any sample interval took),
the accepted steps per simulated second (the same two), the resident memory at the end and its
growth over the second half of the run, the largest balance error relative to the energy scale,
and how the run ended. CPU seconds are the process's own, so they hold on a loaded machine and
across the pauses of a run resumed from its checkpoint; a resumed run is a new process, whose
resident memory starts from a new baseline, so growth is taken over the second half only.
"""
import csv
import pathlib
import sys

PAPER = ["paper-fig4", "paper-fig5", "paper-fig6", "paper-fig5-self-collision", "paper-fig6-self-collision"]


def ended(verdict_path):
    """'completed', 'FAILED' or 'running' (no verdict yet: the run is going on or was stopped)."""
    if not verdict_path.exists():
        return "running"
    text = verdict_path.read_text()
    if "FAILED" in text or "failed" in text:
        return "FAILED"
    return "completed" if " simulated in " in text else "running"


def row(run, path):
    samples = list(csv.DictReader(path.open()))
    if len(samples) < 2:
        return f"| `{run}` | not started | | | | | | |"
    time = [float(s["time"]) for s in samples]
    cpu = [float(s["cpu_seconds"]) for s in samples]
    steps = [int(s["accepted_steps"]) for s in samples]
    resident = [int(s["resident_bytes"]) for s in samples]
    error = [float(s["error_over_scale"]) for s in samples]
    intervals = range(1, len(samples))
    cpu_rate = [(cpu[i] - cpu[i - 1]) / (time[i] - time[i - 1]) for i in intervals]
    step_rate = [(steps[i] - steps[i - 1]) / (time[i] - time[i - 1]) for i in intervals]
    half = next(i for i, t in enumerate(time) if t >= time[-1] / 2)
    growth = max(r - resident[half] for r in resident[half:])
    return (f"| `{run}` | {time[-1]:g} s | {cpu[-1]:,.0f} s | {cpu[-1] / time[-1]:.3g} s, {max(cpu_rate):.3g} s "
            f"| {steps[-1] / time[-1]:,.0f}, {max(step_rate):,.0f} | {resident[-1] / 2**20:.1f} MiB, {growth:,} bytes "
            f"| {max(error):.2g} | {ended(path.with_suffix('.txt'))} |")


def main():
    results = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "bench/results")
    found = {p.name[len("soak-"):-len(".csv")]: p for p in results.glob("soak-*.csv")}
    order = [r for r in PAPER if r in found] + sorted(r for r in found if r not in PAPER)
    print("| Run | simulated | CPU | CPU per simulated s: mean, most in a sample interval "
          "| steps per simulated s: mean, most | resident memory at the end, growth over the second half "
          "| largest \\|balance error\\| / scale | ended |")
    print("|---|---|---|---|---|---|---|---|")
    for run in order:
        print(row(run, found[run]))


if __name__ == "__main__":
    main()
