#!/usr/bin/env python3
"""The Python layer's overhead (issue 18), measured as ratios within one run so that the
load of a shared machine cancels out:

1. generate: `wisp_bench --benchmark_filter=^BM_Generate100k/1/` (the statistical model of
   100,000 strands × 32 points, 2,000 wisps, one thread) against the same C++ call from
   Python (`wisp._wisp.generate_model`, threads=1, the bench's style built through
   wisp.Style), interleaved: C++, Python, C++, Python, ... CPU time on both sides (the
   bench's cpu_time is its thread's; Python's time.thread_time of the calling thread, which
   runs the whole call in a one-thread arena). Reported: the median of each and the ratio.
2. points: the cost of `hair.points` (a view, O(1)) against `hair.points.copy()` (what a
   copy of 3.2 M points would cost).

    PYTHONPATH=build/release/python python3 bench/python_overhead.py build/release/bin/wisp_bench
"""
import json
import statistics
import subprocess
import sys
import time

import wisp
from wisp import _wisp


def bench_style():
    style = wisp.Style()  # bench/bench_common.hpp's bench_style()
    style.roots.wisps = 2000
    style.roots.strands = 100000
    style.roots.points_per_strand = 32
    style.wisp.length = {"distribution": "constant", "value": 1.0}
    style.prototype.shape = "wavy"
    return style


def cpp_ms(exe, name="^BM_Generate100k/1/", field="cpu_time"):
    out = subprocess.run([exe, f"--benchmark_filter={name}",
                          "--benchmark_min_time=0.5", "--benchmark_format=json"],
                         check=True, capture_output=True, text=True).stdout
    runs = [b for b in json.loads(out)["benchmarks"] if b["run_type"] == "iteration"]
    return runs[0][field]  # ms (the benchmark's unit)


def python_ms(style, head, reps=3):
    times = []
    for _ in range(reps):
        t0 = time.thread_time()
        _wisp.generate_model(style._s, head, 1)
        times.append((time.thread_time() - t0) * 1e3)
    return statistics.median(times)


def main():
    exe = sys.argv[1]
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    style, head = bench_style(), wisp.Head.builtin()
    python_ms(style, head, 1)  # warm up
    cpp, py = [], []
    for r in range(rounds):
        cpp.append(cpp_ms(exe))
        py.append(python_ms(style, head))
        print(f"round {r + 1}: C++ {cpp[-1]:.1f} ms, Python {py[-1]:.1f} ms CPU", flush=True)
    c, p = statistics.median(cpp), statistics.median(py)
    print(f"generate 100k (1 thread, CPU time, median of {rounds} interleaved rounds): "
          f"C++ {c:.1f} ms, Python {p:.1f} ms, ratio {p / c:.3f}")

    # The whole solved pipeline, head field built in the run (as the CLI and wisp.generate
    # do), 2 threads, wall time: noisier on a shared machine, so a rough figure.
    cpp, py = [], []
    for r in range(rounds):
        cpp.append(cpp_ms(exe, "^BM_GenerateSolved100k/0/", "real_time"))
        t0 = time.perf_counter()
        wisp.generate(style, head=head, threads=2)
        py.append((time.perf_counter() - t0) * 1e3)
        print(f"round {r + 1}: C++ {cpp[-1]:.1f} ms, wisp.generate {py[-1]:.1f} ms wall",
              flush=True)
    c, p = statistics.median(cpp), statistics.median(py)
    print(f"solved generate 100k (2 threads, wall, median of {rounds}): C++ {c:.1f} ms, "
          f"wisp.generate {p:.1f} ms, ratio {p / c:.3f}")

    hair = _wisp.generate_model(style._s, head, None)
    n = 100000
    t0 = time.perf_counter()
    for _ in range(n):
        hair.points
    view_us = (time.perf_counter() - t0) / n * 1e6
    t0 = time.perf_counter()
    for _ in range(5):
        hair.points.copy()
    copy_ms = (time.perf_counter() - t0) / 5 * 1e3
    same = hair.points.__array_interface__["data"][0] == hair.points.__array_interface__["data"][0]
    print(f"hair.points ({hair.point_count} points): {view_us:.2f} µs per access, same data "
          f"pointer each time: {same}, base is the Hair: {hair.points.base is hair}; "
          f"a copy would cost {copy_ms:.1f} ms")


if __name__ == "__main__":
    main()
