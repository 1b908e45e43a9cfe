"""The memory check from Python: clothsim.Simulation and clothsim.run refuse a scene too large for
the memory the process may use, at once and before anything is written, with ResourceError (a
MemoryError) carrying the estimate, its parts and the limit; max_memory= moves the limit."""

import os
import time

import pytest

import clothsim

# 4096 x 4096 with implicit Euler: about 77 GiB.
HUGE = {"lattice.rows": 4096, "lattice.cols": 4096, "integrator.method": "implicit-euler"}


def refused(start):
    began = time.monotonic()
    with pytest.raises(clothsim.ResourceError) as error:
        start()
    assert time.monotonic() - began < 5.0  # from the scene's shape, before its model is built
    return error.value


def test_a_huge_scene_is_refused_by_simulation_and_run(tmp_path):
    scene = clothsim.load_scene("paper-fig5", set=HUGE)
    for error in (
        refused(lambda: clothsim.Simulation(scene)),
        refused(lambda: clothsim.run(scene, out=tmp_path / "run", render="none")),
    ):
        assert isinstance(error, MemoryError)
        assert error.estimate > error.limit > 0
        assert "implicit-euler workspace" in error.parts and sum(error.parts.values()) == error.estimate
        assert "the scene needs an estimated" in str(error) and "max_memory=bytes to override" in str(error)
    assert not os.path.exists(tmp_path / "run")
    assert os.listdir(tmp_path) == []


def test_max_memory_refuses_a_small_scene_and_lets_it_through_when_larger(tmp_path):
    scene = clothsim.load_scene("paper-fig5", set={"output.duration": 0.1})
    error = refused(lambda: clothsim.Simulation(scene, max_memory=1000))
    assert error.limit == 1000 and "max_memory allows 1000 bytes" in str(error)
    refused(lambda: clothsim.run(scene, out=tmp_path / "run", render="none", max_memory="1K"))
    assert not os.path.exists(tmp_path / "run")
    assert clothsim.Simulation(scene, max_memory="4G").time == 0.0
    assert clothsim.run(scene, out=tmp_path / "run", render="none", max_memory=4 << 30).status == "completed"


@pytest.mark.parametrize("value", [0, -5, "lots", True, 1.5])
def test_a_bad_max_memory_is_a_scene_error_naming_it(value):
    with pytest.raises(clothsim.SceneError, match="max_memory: must be") as error:
        clothsim.Simulation("paper-fig5", max_memory=value)
    assert error.value.source == "max_memory"
