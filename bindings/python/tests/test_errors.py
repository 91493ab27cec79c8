"""Bad input raises the exception of the library's code, with its message, and changes nothing."""

import numpy as np
import pytest

import wethair


def test_bad_step_is_invalid_argument(paper):
    with wethair.Simulation(paper, backend="cpu") as sim:
        before = sim.vertices().copy()
        for dt in (-1.0, 0.0, float("nan"), float("inf")):
            with pytest.raises(wethair.InvalidArgumentError) as e:
                sim.step(dt)
            assert e.value.code == wethair.Result.ERROR_INVALID_ARGUMENT
            assert "dt" in e.value.message
        np.testing.assert_array_equal(sim.vertices(), before)


def test_nan_water_is_refused_and_nothing_added(paper):
    with wethair.Simulation(paper, backend="cpu") as sim:
        with pytest.raises(wethair.InvalidArgumentError):
            sim.add_water([[0.0, 0.0, 0.2], [np.nan, 0.0, 0.2]])
        assert sim.stats().particles == 0
        with pytest.raises(wethair.InvalidArgumentError, match="shape"):
            sim.add_water([[0.0, 0.0]])


def test_more_water_than_capacity(paper):
    with wethair.Simulation(paper, backend="cpu", water={"capacity": 10}) as sim:
        with pytest.raises(wethair.CapacityError):
            sim.add_water(np.zeros((11, 3)) + [0, 0, 0.3])


def test_bad_parameters(paper):
    with pytest.raises(wethair.InvalidArgumentError, match="substeps"):
        wethair.Simulation(paper, backend="cpu", substeps=0)
    with pytest.raises(wethair.InvalidArgumentError):
        wethair.Simulation(paper, backend="cpu", air_drag=-1.0)
    with pytest.raises(TypeError, match="no parameter 'substep'"):
        wethair.Simulation(paper, substep=4)
    with pytest.raises(ValueError, match="unknown name 'vulkan'"):
        wethair.Simulation(paper, backend="vulkan")
    with pytest.raises(ValueError, match="unknown preset"):
        wethair.Simulation(paper, preset="film")


def test_files_and_handles():
    with pytest.raises(wethair.WetHairIOError) as e:
        wethair.Groom.load("/nonexistent/groom.tfx")
    assert isinstance(e.value, OSError) and e.value.code == wethair.Result.ERROR_IO
    g = wethair.Groom.paper_scene(10, 4)
    g.close()
    g.close()  # idempotent
    with pytest.raises(ValueError, match="closed"):
        wethair.Simulation(g)
    with pytest.raises(wethair.InvalidArgumentError):
        wethair.Groom.from_strands(np.zeros((2, 1, 3)))  # one point per strand


def test_unsupported_and_shape_errors(paper):
    with wethair.Simulation(paper, backend="cpu") as sim:
        with pytest.raises(wethair.UnsupportedError):
            sim.set_guide_fraction(0.5)  # no guides
        with pytest.raises(wethair.InvalidArgumentError):
            sim.set_head_transform(np.eye(3))
        with pytest.raises(wethair.InvalidArgumentError):
            sim.vertices(out=np.zeros(5, np.float32))
        sim.close()
        with pytest.raises(ValueError, match="closed"):
            sim.step()
