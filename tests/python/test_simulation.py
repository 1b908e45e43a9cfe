"""clothsim.Simulation: stepping frame by frame gives the command's run bit for bit; energies,
live edits and errors."""

import math
import threading

import numpy
import pytest

import clothsim
from conftest import energy_rows, short_scene


@pytest.mark.parametrize("name, duration", [("paper-fig5", 2.0), ("paper-fig4", 0.25)])
def test_stepping_frame_by_frame_gives_the_commands_positions_bit_for_bit(run_command, tmp_path, name, duration):
    scene = short_scene(name, duration)
    run_command("run", name, "--set", f"output.duration={duration}", "--render", "none", "--out", "run", "--quiet")
    positions = numpy.load(tmp_path / "run" / "positions.npy")
    velocities = numpy.load(tmp_path / "run" / "velocities.npy")
    assert positions.shape == (scene.frames, scene.particles, 3)

    by_time = clothsim.Simulation(scene)
    by_step = clothsim.Simulation(scene)
    assert numpy.array_equal(by_time.positions, positions[0])
    for k in range(1, scene.frames):
        by_time.advance_to(k / scene.fps)  # Python's division is the run's: clothsim.frame_time(k, fps)
        by_step.step()
        assert by_time.time == clothsim.frame_time(k, scene.fps) == by_step.time
        assert numpy.array_equal(by_time.positions, positions[k]), f"frame {k}"
        assert numpy.array_equal(by_time.velocities, velocities[k]), f"frame {k}"
        assert numpy.array_equal(by_step.positions, positions[k]), f"frame {k}"


def test_energy_has_the_terms_of_energy_csv_with_its_values(run_command, tmp_path):
    run_command("run", "paper-fig5", "--set", "output.duration=0.5", "--render", "none", "--out", "run", "--quiet")
    rows = energy_rows(tmp_path / "run")
    scene = short_scene("paper-fig5", 0.5)
    simulation = clothsim.Simulation(scene)
    # Frame by frame, as the run steps: adaptive steps land on every requested time, so one
    # advance_to(0.5) takes other steps and ends a little elsewhere.
    for _ in range(1, scene.frames):
        simulation.step()
    energy = simulation.energy()
    shared = [name for name in energy if name in rows]
    assert set(shared) == {
        "time", "kinetic", "gravitational", "connector", "radial_adjacent", "radial_opposite", "total",
        "damping_work", "drag_work", "anchor_work", "balance_error", "plastic_work", "fracture_work", "contact_work",
    }
    for name in shared:
        assert energy[name] == rows[name][-1], name  # energy.csv holds %.17g: exact
    works = ["damping_work", "drag_work", "anchor_work", "edit_work", "plastic_work", "fracture_work", "contact_work"]
    assert energy["balance_error"] == energy["total"] - (energy["initial_total"] + sum(energy[w] for w in works))


def test_an_undamped_sheet_keeps_its_energy():
    scene = short_scene(
        "paper-fig5", 1.0,
        **{"springs.connector.damping": 0, "springs.adjacent.damping": 0, "springs.opposite.damping": 0,
           "environment.air_drag": 0},
    )
    simulation = clothsim.Simulation(scene)
    simulation.advance_to(1.0)
    energy = simulation.energy()
    assert energy["damping_work"] == 0 and energy["drag_work"] == 0
    swing = abs(energy["gravitational"])  # the energy that moved between terms
    assert swing > 1.0
    assert abs(energy["total"] - energy["initial_total"]) < 1e-5 * swing


def test_auto_precision_reports_its_windows_and_goes_on_as_the_command_does(run_command, tmp_path):
    # `precision: auto` on the CPU chooses float32 or float64 frame by frame (sim/precision_choice.h):
    # the paper's Figure 5 runs every frame in float32 once it moves, as `clothsim run` does.
    run_command("run", "paper-fig5", "--set", "output.duration=0.5", "--precision", "auto", "--render", "none",
                "--out", "run", "--quiet")
    positions = numpy.load(tmp_path / "run" / "positions.npy")
    scene = short_scene("paper-fig5", 0.5, precision="auto")
    simulation = clothsim.Simulation(scene)
    for k in range(1, scene.frames):
        simulation.advance_to(k / scene.fps)
    assert numpy.array_equal(simulation.positions, positions[-1])
    statistics = simulation.statistics()
    assert statistics["float32_windows"] == scene.frames - 1
    assert statistics["float64_windows"] == 0
    assert statistics["rest_steps"] >= 1
    assert 0 < statistics["largest_drift"] <= 0.25 * 1e-6


def test_live_edits_change_the_run_and_book_their_energy():
    scene = short_scene("paper-fig5", 1.0)
    plain = clothsim.Simulation(scene)
    edited = clothsim.Simulation(scene)
    plain.advance_to(0.5)
    edited.advance_to(0.5)
    edited.set({"environment.gravity": [0, -4.9, 0], "springs.connector.stiffness": 100})
    assert edited.scene.to_dict()["environment"]["gravity"] == [0, -4.9, 0]
    assert edited.energy()["edit_work"] != 0  # halving gravity changes the potential energy at once
    plain.advance_to(1.0)
    edited.advance_to(1.0)
    assert not numpy.array_equal(plain.positions, edited.positions)
    with pytest.raises(clothsim.SceneError, match="cannot change while the simulation runs") as error:
        edited.set({"lattice.rows": 3})
    assert error.value.field == "lattice.rows"
    with pytest.raises(clothsim.SceneError):
        edited.set({"springs.connector.stiffness": 50, "environment.air_drag": -1})
    assert edited.scene.to_dict()["springs"]["connector"]["stiffness"] == 100  # nothing applied


def test_time_only_goes_forward_and_a_failure_raises_simulation_error():
    simulation = clothsim.Simulation(short_scene("paper-fig5", 1.0))
    simulation.advance_to(0.1)
    with pytest.raises(ValueError):
        simulation.advance_to(0.05)
    with pytest.raises(ValueError):
        simulation.advance_to(math.nan)
    # rk4 far past its stable step blows up: the diagnosis names the time.
    unstable = clothsim.Simulation(
        short_scene("paper-fig5", 5.0, **{"integrator.method": "rk4", "integrator.time_step": 0.05})
    )
    with pytest.raises(clothsim.SimulationError, match="simulation failed") as error:
        unstable.advance_to(5.0)
    assert isinstance(error.value, RuntimeError)
    assert unstable.failure is not None and unstable.failure in str(error.value)
    assert unstable.time < 5.0 and numpy.all(numpy.isfinite(unstable.positions))


def test_positions_are_copies_and_other_threads_run_while_one_steps():
    simulation = clothsim.Simulation(short_scene("paper-fig5", 1.0))
    positions = simulation.positions
    positions[:] = 0.0
    assert not numpy.array_equal(simulation.positions, positions)
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(1)
            stop.wait(0.001)

    ticker = threading.Thread(target=tick)
    ticker.start()
    try:
        simulation.advance_to(1.0)  # the GIL is released while it steps
    finally:
        stop.set()
        ticker.join()
    assert len(ticks) > 1


@pytest.mark.parametrize("method", ["rkf45", "implicit-euler"])
@pytest.mark.parametrize("self_collision", [False, True])
def test_eight_simulations_on_eight_threads_give_the_bits_of_eight_in_a_row(method, self_collision):
    def scene(k):
        values = {"integrator.method": method, "collision.self": self_collision, "threads": 1,
                  "springs.connector.stiffness": 1400 * (1 + 0.05 * k)}
        if method == "implicit-euler":
            values["integrator.time_step"] = 1 / 240
        return short_scene("paper-fig5", 0.5, **values)

    def run(k):
        simulation = clothsim.Simulation(scene(k))
        simulation.advance_to(0.5)
        return simulation.positions, simulation.velocities

    alone = [run(k) for k in range(8)]
    together = [None] * 8

    def work(k):
        together[k] = run(k)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(8)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    for k in range(8):
        assert numpy.array_equal(alone[k][0], together[k][0]) and numpy.array_equal(alone[k][1], together[k][1]), k
    assert not numpy.array_equal(alone[0][0], alone[1][0])
