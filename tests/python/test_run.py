"""clothsim.run(): the command's output folder, written by the same driver."""

import json
import os

import numpy
import pytest

import clothsim
from conftest import short_scene

# Files whose bytes depend only on the scene: the same from the command and from Python.
SAME_BYTES = [
    "positions.npy", "velocities.npy", "energy.csv", "final.obj", "scene.json", "connectors.npy",
    "connector_break_time.npy", "connector_rest_length.npy",
]


def test_run_writes_the_commands_folder(run_command, tmp_path):
    run_command("run", "paper-fig5", "--set", "output.duration=1", "--render", "none", "--export", "pc2",
                "--out", "command", "--quiet")
    scene = short_scene("paper-fig5", 1.0, **{"output.export": "pc2"})
    result = clothsim.run(scene, out=tmp_path / "python", render="none")
    assert result.status == "completed" and result.frames == scene.frames
    assert result.out == str(tmp_path / "python")
    command, python = tmp_path / "command", tmp_path / "python"
    assert sorted(os.listdir(command)) == sorted(os.listdir(python))
    for name in SAME_BYTES + ["animation.pc2", "rest.obj"]:
        assert (command / name).read_bytes() == (python / name).read_bytes(), name
    ours, theirs = (json.loads((folder / "summary.json").read_text()) for folder in (python, command))
    for key in ("status", "scene", "lattice", "frames", "fps", "simulated_time", "energy", "files"):
        assert ours[key] == theirs[key], key
    assert ours["command_line"].startswith("python3: clothsim.run('paper-fig5'")
    # The result's simulation is at the last frame.
    assert numpy.array_equal(result.simulation.positions, numpy.load(python / "positions.npy")[-1])


def test_run_writes_the_report_when_asked(tmp_path):
    result = clothsim.run(short_scene("paper-fig5", 0.2), out=tmp_path / "run", render="none", report=True)
    page = (tmp_path / "run" / "report.html").read_text()
    assert result.status == "completed"
    assert '<script type="importmap">' in page and '"total_frames":13' in page
    assert not (tmp_path / "plain").exists()
    clothsim.run(short_scene("paper-fig5", 0.2), out=tmp_path / "plain", render="none")
    assert not (tmp_path / "plain" / "report.html").exists()


@pytest.mark.skipif(not clothsim.has_render, reason="built without CLOTHSIM_BUILD_RENDER")
def test_run_makes_the_picture_unless_render_is_none(tmp_path):
    result = clothsim.run(short_scene("paper-fig5", 0.1), out=tmp_path / "run", render="image", size=(64, 48),
                          samples=1)
    assert (tmp_path / "run" / "final.png").read_bytes().startswith(b"\x89PNG")
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["files"]["final.png"]["width"] == 64
    assert result.status == "completed"


def test_bad_input_writes_nothing_and_a_failed_run_keeps_its_folder(tmp_path):
    with pytest.raises(clothsim.SceneError, match="--render"):
        clothsim.run("paper-fig5", out=tmp_path / "a", render="sometimes")
    (tmp_path / "not-a-run").mkdir()
    (tmp_path / "not-a-run" / "notes.txt").write_text("mine")
    with pytest.raises(clothsim.SceneError) as error:
        clothsim.run("paper-fig5", out=tmp_path / "not-a-run", render="none")
    assert error.value.source == "out"
    assert not (tmp_path / "a").exists() and (tmp_path / "not-a-run" / "notes.txt").read_text() == "mine"

    unstable = short_scene("paper-fig5", 5.0, **{"integrator.method": "rk4", "integrator.time_step": 0.05})
    with pytest.raises(clothsim.SimulationError, match="are kept in") as failed:
        clothsim.run(unstable, out=tmp_path / "failed", render="none", quiet=True)
    result = failed.value.result
    assert result.status == "failed" and 0 < result.frames < unstable.frames
    summary = json.loads((tmp_path / "failed" / "summary.json").read_text())
    assert summary["status"] == "failed"
    assert numpy.load(tmp_path / "failed" / "positions.npy").shape[0] == result.frames


def test_resume_goes_on_from_a_checkpoint_as_the_command_does(tmp_path):
    scene = short_scene("paper-fig5", 1.0, **{"output.checkpoint_every": 0.25})
    whole = clothsim.run(scene, out=tmp_path / "whole", render="none", quiet=True)
    # A run killed after its checkpoints leaves its partial folder; here one is made by hand from
    # a complete run's: the folder marked interrupted, as an interrupted run leaves it.
    clothsim.run(scene, out=tmp_path / "cut", render="none", quiet=True)
    summary_path = tmp_path / "cut" / "summary.json"
    summary = json.loads(summary_path.read_text())
    if not (tmp_path / "cut" / "checkpoints").exists():
        pytest.skip("a completed run keeps no checkpoints")
    summary["status"] = "interrupted"
    summary_path.write_text(json.dumps(summary))
    resumed = clothsim.resume(tmp_path / "cut", quiet=True)
    assert resumed.status == "completed"
    for name in SAME_BYTES:
        assert (tmp_path / "whole" / name).read_bytes() == (tmp_path / "cut" / name).read_bytes(), name
    assert whole.frames == resumed.frames
