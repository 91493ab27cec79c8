"""The paper scene and the wet model through the Python package: the physics is the
library's; these check that the binding carries it faithfully."""

import numpy as np
import pytest

import wethair

from conftest import require_gpu

DT = 1.0 / 60.0


def shower(sim, n=400, seed=3):
    """n drops in a disc 4 cm above the 0.1 m head, falling."""
    rng = np.random.default_rng(seed)
    a = rng.uniform(0, 2 * np.pi, n)
    r = 0.07 * np.sqrt(rng.uniform(0, 1, n))
    p = np.stack([r * np.cos(a), r * np.sin(a), np.full(n, 0.14)], axis=1)
    sim.add_water(p, np.tile([0.0, 0.0, -0.5], (n, 1)))


def test_roots_stay_tips_fall_and_water_clumps(paper):
    with wethair.Simulation(paper, preset="paper", backend="cpu", colliders=[wethair.sphere((0, 0, 0), 0.1)]) as dry, \
         wethair.Simulation(paper, preset="paper", backend="cpu", colliders=[wethair.sphere((0, 0, 0), 0.1)]) as wet:
        rest = dry.strands().copy()
        shower(wet)
        for _ in range(90):
            dry.step(DT)
            wet.step(DT)
        x = dry.strands()
        assert x.shape == (1000, 6, 3)
        # Roots pinned to the head exactly; tips sag under gravity.
        assert np.abs(x[:, 0] - rest[:, 0]).max() < 1e-6
        assert np.linalg.norm(x[:, -1] - rest[:, -1], axis=1).mean() > 0.01
        assert np.isfinite(x).all()
        # Water gathers the strands: the library's clumping statistic drops by a tenth or more.
        d, w = dry.stats(), wet.stats()
        assert w.particles > 0 and d.particles == 0
        assert w.clumping < 0.9 * d.clumping, (w.clumping, d.clumping)


def test_a_strand_at_rest_stays_at_rest_without_gravity():
    strand = np.stack([np.zeros(8), np.zeros(8), -0.01 * np.arange(8)], axis=1)
    with wethair.Groom.from_strands([strand, strand + [0.05, 0, 0]]) as g, \
         wethair.Simulation(g, backend="cpu", gravity=(0, 0, 0)) as sim:
        before = sim.positions().copy()
        np.testing.assert_array_equal(before, np.concatenate([strand, strand + [0.05, 0, 0]]).astype(np.float32))
        for _ in range(60):
            sim.step(DT)
        assert np.abs(sim.positions() - before).max() < 1e-6


def test_ragged_strands_and_vertex_output_into_a_given_array():
    strands = [np.stack([np.full(n, 0.01 * i), np.zeros(n), -0.01 * np.arange(n)], axis=1) for i, n in enumerate((3, 7, 5))]
    with wethair.Groom.from_strands(strands) as g, wethair.Simulation(g, backend="cpu") as sim:
        assert g.counts == (3, 15)
        lay = sim.layout
        assert (lay.vertex_count, lay.strand_count) == (15, 3)
        out = np.zeros((lay.vertex_count, lay.stride), np.float32)
        got = sim.vertices(out=out)
        assert np.shares_memory(got, out)  # written in place, no copy
        np.testing.assert_allclose(out[:, lay.position_offset : lay.position_offset + 3], np.concatenate(strands), atol=1e-7)
        with pytest.raises(ValueError):
            sim.strands()  # strands differ in point count


def test_wet_model_ledger_balances_and_soaked_hair_hangs_lower(paper):
    kw = dict(backend="cpu", colliders=[wethair.sphere((0, 0, 0), 0.1)], held_water={"enabled": True})
    with wethair.Simulation(paper, **kw) as dry, wethair.Simulation(paper, **kw) as wet:
        wet.soak(1.0)
        # Two seconds: soaked hair, 2.3 times as heavy, swings slower, and half a second in it
        # is still on its first swing (its tips were higher than the dry twin's then).
        for _ in range(120):
            dry.step(DT)
            wet.step(DT)
        s = wet.stats()
        assert s.water_added > 0
        assert s.water_added == s.water_in_particles + s.water_held + s.water_left + s.water_evaporated
        assert s.water_held_kg > 0
        # Water's weight: soaked tips hang lower than dry ones.
        assert wet.strands()[:, -1, 2].mean() < dry.strands()[:, -1, 2].mean() - 1e-3
        assert wet.wetness().max() > 0.5 and dry.wetness().max() == 0.0


def test_weather_emitters_add_drops(paper):
    with wethair.Simulation(paper, backend="cpu") as sim:
        sim.set_spray(origin=(0, -0.3, 0.1), direction=(0, 1, 0), half_angle=0.2, rate=600, speed=3)
        sim.set_wind((1.0, 0.0, 0.0), gust=0.3, seed=2)
        for _ in range(20):
            sim.step(DT)
        assert sim.stats().particles > 0
        assert sim.water().shape == (sim.stats().particles, 3)
        c = sim.counters()
        assert (c.particles, c.steps) == (sim.stats().particles, 20)
        assert c.clumping == -1.0 and sim.stats().clumping > 0
        sim.set_spray(None)
        sim.set_rain(center=(0, 0, 0.4), rate=300)
        sim.set_rain(None)


def test_guides_fraction_and_fixed_steps(paper):
    with wethair.Simulation(paper, backend="cpu", guides={"choice": "every_nth", "count": 4}) as sim:
        assert sim.layout.vertex_count == 6000  # every strand is written
        sim.set_guide_fraction(0.5)
        for _ in range(5):
            sim.step(DT)
        assert np.isfinite(sim.positions()).all()
    with wethair.Simulation(paper, backend="cpu", fixed_step=1 / 120) as sim:
        a = sim.advance(1 / 60)
        assert a.steps == 2


def test_deterministic_run_after_run(paper):
    runs = []
    for _ in range(2):
        with wethair.Simulation(paper, preset="paper", backend="cpu") as sim:
            shower(sim)
            for _ in range(20):
                sim.step(DT)
            runs.append(sim.vertices().tobytes())
    assert runs[0] == runs[1]


def test_gpu_backend_matches_the_cpu(paper):
    try:
        gpu = wethair.Simulation(paper, preset="paper", backend="gpu")
    except (wethair.DeviceError, wethair.UnsupportedError) as e:
        if require_gpu():
            raise
        pytest.skip(f"no GPU adapter: {e}")
    with gpu, wethair.Simulation(paper, preset="paper", backend="cpu") as cpu:
        assert gpu.backend_info().backend == wethair.Backend.GPU
        for _ in range(10):
            gpu.step(DT)
            cpu.step(DT)
        # The backends' f32 sums round differently: within 10 micrometres after 10 frames.
        assert np.abs(gpu.positions() - cpu.positions()).max() < 1e-5


def test_head_transform_and_root_frames_in_numpys_convention(paper):
    """A 4 x 4 matrix with the translation in its last column moves the roots there (the
    package hands C its column-major floats); skinned roots land on their frames."""
    with wethair.Simulation(paper, backend="cpu") as sim:
        rest = sim.strands()[:, 0].copy()
        m = np.eye(4)
        m[:3, 3] = (0.05, -0.02, 0.01)
        c, s = np.cos(0.3), np.sin(0.3)
        m[:2, :2] = [[c, -s], [s, c]]  # a turn of 0.3 rad about z
        sim.set_head_transform(m)
        sim.step(DT)
        want = rest @ m[:3, :3].T + m[:3, 3]
        assert np.abs(sim.strands()[:, 0] - want).max() < 1e-6
    with wethair.Simulation(paper, backend="cpu", skinned_roots=True) as sim:
        rest = sim.strands()[:, 0].copy()
        target = rest + [0.0, 0.0, 0.05]
        quats = np.tile([0.0, 0.0, 0.0, 1.0], (len(rest), 1))
        sim.set_root_frames(target, quats)
        sim.step(DT)
        assert np.abs(sim.strands()[:, 0] - target).max() < 1e-6
        with pytest.raises(wethair.InvalidArgumentError):
            sim.set_root_frames(target[:-1], quats[:-1])  # one short


def test_a_capsule_on_its_own_frame_lifts_the_hair(paper):
    """``collider_frames`` puts a collider in a frame of its own (a bone) that
    ``set_collider_transform`` moves (4 x 4, translation in the last column): a bar raised
    into the hanging hair leaves no free point inside it and holds hair on it. Colliders on the
    head refuse a frame; a frame per collider is required."""
    bar = wethair.capsule((-0.25, 0.0, 0.0), (0.25, 0.0, 0.0), 0.03)
    m = np.eye(4)
    m[2, 3] = -0.4
    with wethair.Simulation(paper, backend="cpu", colliders=[bar], collider_frames=[m]) as sim:
        for f in range(1, 91):
            m[2, 3] = -0.4 + 0.35 * min(1.0, f / 60)
            sim.set_collider_transform(0, m)
            sim.step(DT)
        free = sim.strands()[:, 1:].reshape(-1, 3)
        over = np.maximum(np.abs(free[:, 0]) - 0.25, 0.0)
        d = np.sqrt(over**2 + free[:, 1] ** 2 + (free[:, 2] + 0.05) ** 2)
        assert d.min() > 0.03 - 1e-5
        assert (d < 0.032).sum() > 20
    with wethair.Simulation(paper, backend="cpu", colliders=[bar]) as sim:
        with pytest.raises(wethair.UnsupportedError):
            sim.set_collider_transform(0, np.eye(4))
    with pytest.raises(wethair.InvalidArgumentError):
        wethair.Simulation(paper, backend="cpu", colliders=[bar], collider_frames=[])


def test_a_real_groom_loads_in_metres_and_settles(root):
    """The TressFX ponytail (centimetres, y up in the file) through the load desc's keywords."""
    with wethair.Groom.load(root / "tests/data/ponytail_back.tfx", scale=0.01, up_axis="y_to_z") as g:
        assert g.counts == (517, 517 * 16)
        with wethair.Simulation(g, backend="cpu") as sim:
            x0 = sim.positions().copy()
            extent = x0.max(axis=0) - x0.min(axis=0)
            assert 0.05 < extent.max() < 1.0  # metres, not centimetres
            for _ in range(30):
                sim.step(DT)
            x = sim.positions()
            assert np.isfinite(x).all() and np.abs(x - x0).max() < 0.5
