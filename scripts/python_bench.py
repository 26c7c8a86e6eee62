#!/usr/bin/python3
"""What rendering into NumPy costs against the CLI's renderer: the paper's scene (23 frames at full
resolution by default) rendered by skypol.render_stack, against `skypol bench --render-only` on the
same scene and frames (camera rays + frame memory once + the sky of every frame into a reused
frame: what `skypol render` spends before it writes). Rounds alternate CLI and Python so that both
see the same load from other processes; the load average is printed beside every figure.
Figures only, nothing asserted (docs/python.md quotes them).

    scripts/python_bench.py [--scene S] [--rounds N] [--set key=value ...] [--skypol build/skypol]
"""

import argparse
import gc
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def load():
    return "load average %.2f %.2f %.2f" % os.getloadavg()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default=os.path.join(ROOT, "scenes", "skypole-marseille.toml"))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--set", action="append", default=[], help="scene override, as skypol --set")
    ap.add_argument("--skypol", default=os.path.join(ROOT, "build", "skypol"))
    a = ap.parse_args()
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(a.skypol)), "python"))
    import skypol

    scene = skypol.load_scene(a.scene, overrides=a.set)
    frames = len(scene.times)
    cam = scene.camera
    print(f"scene {a.scene}{' ' + ' '.join(a.set) if a.set else ''}: {frames} frames, {cam.width}x{cam.height} px, "
          f"channels {scene.channel_names}; {os.cpu_count()} hardware threads")
    # bench --render-only takes no --set: give it the scene as loaded (overrides merged).
    scene_file = a.scene
    if a.set:
        scene_file = os.path.join(ROOT, "out", "python-bench-scene.toml")
        os.makedirs(os.path.dirname(scene_file), exist_ok=True)
        with open(scene_file, "w") as f:
            f.write(scene.text)
    cli_s, py_s, it_s = [], [], []
    for r in range(a.rounds):
        before = load()
        out = subprocess.run([a.skypol, "bench", scene_file, "--render-only", "-n", str(frames), "--json",
                              "--scratch", os.path.join(ROOT, "out", "python-bench-scratch")],
                             capture_output=True, text=True, check=True, cwd=ROOT).stdout
        b = json.loads(out)
        c = (b["ray_setup_ms"] + b["frame_alloc_ms"] + frames * b["sky_render_ms_per_frame"]) / 1e3
        gc.collect()
        t0 = time.perf_counter()
        stack = skypol.render_stack(scene)
        p = time.perf_counter() - t0
        assert len(stack) == frames
        del stack
        gc.collect()
        # The same frames one at a time into one frame's memory, each handed to NumPy (a view).
        t0 = time.perf_counter()
        seen = sum(1 for f in skypol.iter_frames(scene) if f["DoLP.Y" if "DoLP.Y" in f.channels else next(iter(f.channels))].size)
        q = time.perf_counter() - t0
        assert seen == frames
        cli_s.append(c)
        py_s.append(p)
        it_s.append(q)
        print(f"round {r + 1}: CLI render without the file {c:6.2f} s (rays {b['ray_setup_ms'] / 1e3:.2f} s, "
              f"frame memory {b['frame_alloc_ms'] / 1e3:.2f} s, sky {b['sky_render_ms_per_frame']:.0f} ms/frame) | "
              f"Python render_stack (all frames held) {p:6.2f} s = {p / c:.2f}x | "
              f"Python iter_frames {q:6.2f} s = {q / c:.2f}x   [{before}; after: {load()}]", flush=True)
    print(f"best of {a.rounds}: CLI {min(cli_s):.2f} s, render_stack {min(py_s):.2f} s ({min(py_s) / min(cli_s):.2f}x), "
          f"iter_frames {min(it_s):.2f} s ({min(it_s) / min(cli_s):.2f}x)")


if __name__ == "__main__":
    main()
