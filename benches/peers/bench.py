"""Times every engine on the same scene (scene.py) and writes a markdown table.

    python bench.py [--scenes paper,big] [--engines numpy,warp,taichi,wethair]
                    [--threads 1,2] [--reps 3] [--out DIR]

Each (engine, threads, scene) runs in its own process: it builds the scene (setup time,
JIT included), runs 3 untimed frames, then `reps` repetitions of timed frames (each frame
timed alone; a repetition's figure is its median). The table gives the median over
repetitions, every repetition's median, and cpu/wall (how many cores the engine kept busy).
Separately, each engine runs 10 frames from rest; its positions are compared with NumPy's,
and the largest difference is reported (f32 rounding differs by engine; the scene is
sensitive, so a few micrometres are expected, a millimetre is a different model).
"""

import argparse
import importlib
import json
import os
import statistics
import subprocess
import sys
import time

import numpy as np

import scene as sc

FRAMES = {"paper": 60, "big": 8, "tiny": 5}
AGREE_FRAMES = 10
ENGINES = ["numpy", "warp", "taichi", "wethair"]
# Engines whose thread count can be set; the others run once with their own.
THREADED = {"taichi", "wethair"}


def run_one(engine, threads, scene_name, reps, out):
    strands, points = sc.SCENES[scene_name]
    mod = importlib.import_module(f"eng_{engine}")
    t0 = time.perf_counter()
    e = mod.Engine(strands, points, threads)
    e.step_frame()  # the first frame compiles what a JIT compiles
    setup = time.perf_counter() - t0
    for _ in range(2):
        e.step_frame()
    rep_medians, cpu, wall = [], 0.0, 0.0
    for _ in range(reps):
        times = []
        c0, w0 = time.process_time(), time.perf_counter()
        for _ in range(FRAMES[scene_name]):
            f0 = time.perf_counter()
            e.step_frame()
            times.append((time.perf_counter() - f0) * 1e3)
        cpu += time.process_time() - c0
        wall += time.perf_counter() - w0
        rep_medians.append(statistics.median(times))
    x = e.positions()
    fresh = mod.Engine(strands, points, threads)
    for _ in range(AGREE_FRAMES):
        fresh.step_frame()
    agree = os.path.join(out, f"{engine}_{threads}_{scene_name}.npy")
    np.save(agree, fresh.positions())
    return {
        "engine": engine,
        "version": e.version,
        "backend": e.backend,
        "variant": e.variant,
        "scene": scene_name,
        "strands": strands,
        "points": points,
        "threads": threads,
        "ms_median": statistics.median(rep_medians),
        "rep_medians": rep_medians,
        "cpu_over_wall": cpu / wall,
        "setup_s": setup,
        "sanity": sc.sanity(x, sc.rest_positions(strands, points)),
        "agree_file": agree,
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scenes", default="paper,big")
    ap.add_argument("--engines", default=",".join(ENGINES))
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "target", "peers"))
    ap.add_argument("--max-disagreement", type=float, help="exit 1 when an engine ends further than this (m) from NumPy")
    ap.add_argument("--one", help=argparse.SUPPRESS)
    a = ap.parse_args()
    # Absolute: each run is a child process started in this script's folder.
    a.out = os.path.abspath(a.out)
    os.makedirs(a.out, exist_ok=True)
    if a.one:
        engine, threads, scene_name = a.one.split(":")
        print(json.dumps(run_one(engine, int(threads), scene_name, a.reps, a.out)))
        return
    rows, failed = [], False
    for scene_name in a.scenes.split(","):
        for engine in a.engines.split(","):
            counts = [int(t) for t in a.threads.split(",")] if engine in THREADED else [1]
            for t in counts:
                cmd = [sys.executable, __file__, "--one", f"{engine}:{t}:{scene_name}", "--reps", str(a.reps), "--out", a.out]
                p = subprocess.run(cmd, capture_output=True, text=True, cwd=os.path.dirname(os.path.abspath(__file__)))
                if p.returncode != 0:
                    print(f"{engine} x{t} {scene_name}: failed\n{p.stderr[-2000:]}", file=sys.stderr)
                    failed = True
                    continue
                row = json.loads(p.stdout.strip().splitlines()[-1])
                rows.append(row)
                print(f"{engine:8s} x{t} {scene_name:6s} {row['ms_median']:9.2f} ms/frame", file=sys.stderr)
    ref = {r["scene"]: np.load(r["agree_file"]) for r in rows if r["engine"] == "numpy"}
    lines = [
        "| engine | version | backend | scene (strands x points) | ms/frame, median | each repetition | cpu/wall | setup s | after the run: max radius m, max strain | 10 frames vs NumPy, max m |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        x = np.load(r["agree_file"])
        d = float(np.abs(x - ref[r["scene"]]).max()) if r["scene"] in ref else float("nan")
        if a.max_disagreement is not None and not d <= a.max_disagreement:
            print(f"{r['engine']} x{r['threads']} {r['scene']}: {d} m from NumPy", file=sys.stderr)
            failed = True
        _, radius, strain = r["sanity"]
        lines.append(
            f"| {r['engine']} | {r['version']} | {r['backend']} | {r['scene']} ({r['strands']}x{r['points']}) "
            f"| {r['ms_median']:.2f} | {', '.join(f'{m:.2f}' for m in r['rep_medians'])} | {r['cpu_over_wall']:.2f} "
            f"| {r['setup_s']:.1f} | {radius:.3f}, {strain:.2f} | {d:.1e} |"
        )
    table = "\n".join(lines)
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write(table + "\n")
    print(table)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
