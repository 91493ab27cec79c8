"""The Python package reads the same vertices as a C host: examples/c/dump_vertices runs the
paper scene through the C API and writes its vertex buffer; the same run here gives the
same bytes."""

import subprocess

import numpy as np

import wethair


def test_vertices_equal_what_the_c_host_reads(root, tmp_path):
    exe = root / "examples/c/build/dump_vertices"
    assert exe.exists(), "build the C hosts first: make -C examples/c"
    out = tmp_path / "c.bin"
    subprocess.run([str(exe), "500", "30", str(out)], check=True, capture_output=True)
    c = np.fromfile(out, dtype=np.float32)

    i = np.arange(40)
    grid = np.zeros((40, 3), np.float32)  # as the C host computes it, in float
    grid[:, 0] = ((i % 8).astype(np.float32) - np.float32(3.5)) * np.float32(0.01)
    grid[:, 1] = ((i // 8).astype(np.float32) - np.float32(2.0)) * np.float32(0.01)
    grid[:, 2] = np.float32(0.13)
    with wethair.Groom.paper_scene(500, 6) as g:
        # The C host uses wethair_sim_desc_default (the 0.1.0 layout's paper parameters) and
        # the head sphere.
        with wethair.Simulation(g, preset="paper", backend="cpu", colliders=[wethair.sphere((0, 0, 0), 0.1)]) as sim:
            sim.add_water(grid)
            for _ in range(30):
                sim.step(1.0 / 60.0)
            py = sim.vertices()
    assert c.size == py.size
    if c.tobytes() != py.tobytes():
        raise AssertionError(f"vertices differ by up to {np.abs(c - py.ravel()).max()}")
