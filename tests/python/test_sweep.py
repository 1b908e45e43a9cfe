"""clothsim.sweep(): the command's sweep from Python, here and on a Dask cluster (docs/batch.md)."""

import csv
import json
import os
import pickle

import pytest

import clothsim
from test_run import SAME_BYTES

# A 2 x 2 grid of short paper-fig5 runs.
PARAMS = {"springs.adjacent.stiffness": [4, 40], "output.fps": [30, 60]}
PARAM_FLAGS = ["--param", "springs.adjacent.stiffness=4,40", "--param", "output.fps=30,60"]
RUN_FOLDERS = ["run-0000", "run-0001", "run-0002", "run-0003"]


def short_fig5():
    return clothsim.load_scene("paper-fig5", set={"output.duration": 0.25})


def index_rows(folder):
    with open(folder / "index.csv", newline="") as file:
        return list(csv.DictReader(file))


def assert_same_runs(ours, theirs):
    """Every run folder holds the same files, the scene's bytes the same, summary.json alike."""
    for run in RUN_FOLDERS:
        a, b = ours / run, theirs / run
        assert sorted(os.listdir(a)) == sorted(os.listdir(b)), run
        for name in SAME_BYTES:
            assert (a / name).read_bytes() == (b / name).read_bytes(), f"{run}/{name}"
        sa, sb = (json.loads((folder / "summary.json").read_text()) for folder in (a, b))
        for key in ("status", "scene", "lattice", "frames", "fps", "simulated_time", "energy", "integrator"):
            assert sa[key] == sb[key], f"{run}: {key}"


def test_a_sweep_in_this_process_writes_the_commands_folders(run_command, tmp_path):
    run_command("sweep", "paper-fig5", "--set", "output.duration=0.25", *PARAM_FLAGS, "--render", "none",
                "--out", "command", "--quiet")
    counts = clothsim.sweep(short_fig5(), PARAMS, out=tmp_path / "python", render="none", quiet=True)
    assert counts["runs"] == 4 and counts["completed"] == 4 and counts["failed"] == 0
    assert counts["index"] == str(tmp_path / "python" / "index.csv")
    assert_same_runs(tmp_path / "python", tmp_path / "command")
    rows = index_rows(tmp_path / "python")
    assert [row["folder"] for row in rows] == RUN_FOLDERS
    assert [(row["springs.adjacent.stiffness"], row["output.fps"]) for row in rows] == [
        ("4", "30"), ("4", "60"), ("40", "30"), ("40", "60")]
    assert all(row["status"] == "completed" for row in rows)
    # The frame rate swept: 0.25 s at 30 and at 60 frames per second.
    assert [int(row["frames"]) for row in rows] == [9, 16, 9, 16]


def test_a_sweep_on_a_dask_cluster_of_two_workers_writes_the_commands_folders(run_command, tmp_path):
    import distributed  # Debian's python3-distributed (scripts/install-deps.sh)
    run_command("sweep", "paper-fig5", "--set", "output.duration=0.25", *PARAM_FLAGS, "--render", "none",
                "--out", "command", "--quiet")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        counts = clothsim.sweep(short_fig5(), PARAMS, out=tmp_path / "dask", client=client, render="none",
                                quiet=True)
        # The runs went to the workers: each is a task the scheduler knows.
        assert len(client.scheduler_info()["workers"]) == 2
    assert counts["completed"] == 4
    assert_same_runs(tmp_path / "dask", tmp_path / "command")


def test_a_sweep_called_again_runs_only_what_is_not_complete(tmp_path):
    out = tmp_path / "sweep"
    clothsim.sweep(short_fig5(), PARAMS, out=out, render="none", quiet=True)
    before = {run: (out / run / "positions.npy").stat().st_mtime_ns for run in RUN_FOLDERS}
    # One run lost: the sweep again makes that one and leaves the others.
    for name in os.listdir(out / "run-0002"):
        os.remove(out / "run-0002" / name)
    os.rmdir(out / "run-0002")
    assert index_rows(out)[2]["status"] == "completed"
    counts = clothsim.sweep(short_fig5(), PARAMS, out=out, render="none", quiet=True)
    assert counts["completed"] == 4
    after = {run: (out / run / "positions.npy").stat().st_mtime_ns for run in RUN_FOLDERS}
    assert [before[run] == after[run] for run in RUN_FOLDERS] == [True, True, False, True]
    # Another grid into the same folder is refused, naming out.
    with pytest.raises(clothsim.SceneError, match="holds another sweep") as error:
        clothsim.sweep(short_fig5(), {"output.fps": [24]}, out=out, render="none")
    assert error.value.source == "out"


def test_bad_input_stops_the_sweep_before_it_writes_anything(tmp_path):
    out = tmp_path / "bad"
    with pytest.raises(clothsim.SceneError, match="-5") as error:
        clothsim.sweep(short_fig5(), {"output.fps": [30, -5]}, out=out, render="none")
    assert error.value.source == "params" and error.value.field == "output.fps"
    # A value that only the whole scene rules out names the run it belongs to.
    with pytest.raises(clothsim.SceneError, match=r"run-0001, integrator.min_step=0.5"):
        clothsim.sweep(short_fig5(), {"integrator.min_step": [1e-10, 0.5]}, out=out, render="none")
    with pytest.raises(clothsim.SceneError, match="no such key|unknown"):
        clothsim.sweep(short_fig5(), {"springs.nope": [1]}, out=out, render="none")
    with pytest.raises(clothsim.SceneError, match="twice"):
        clothsim.sweep(short_fig5(), {"output.fps": [30, 30]}, out=out, render="none")
    with pytest.raises(clothsim.SceneError, match="list of values"):
        clothsim.sweep(short_fig5(), {"output.fps": 30}, out=out, render="none")
    with pytest.raises(clothsim.SceneError):
        clothsim.sweep(short_fig5(), {}, out=out, render="none")
    assert not out.exists()


def test_a_failed_run_is_failed_in_the_index_and_the_others_complete(tmp_path):
    # rk4 blows up on the paper's material at 0.05 s steps; 0.2 ms is below its stable step (0.43 ms).
    scene = clothsim.load_scene("paper-fig5", set={"output.duration": 1.0, "integrator.method": "rk4"})
    counts = clothsim.sweep(scene, {"integrator.time_step": [0.0002, 0.05]}, out=tmp_path / "s", render="none",
                            quiet=True)
    assert counts["completed"] == 1 and counts["failed"] == 1
    assert [row["status"] for row in index_rows(tmp_path / "s")] == ["completed", "failed"]


def test_a_task_pickles_as_its_scene_and_assignments(tmp_path):
    # What a worker gets: the task rebuilt from its pickle makes the run it stands for.
    state = (short_fig5().to_json(0), str(tmp_path), 0, "run-0000", [("output.fps", "30")],
             {"render": "none", "quiet": True})
    task = clothsim.SweepTask.__new__(clothsim.SweepTask)
    task.__setstate__(state)
    copy = pickle.loads(pickle.dumps(task))
    assert copy.folder == "run-0000" and copy.__getstate__() == state
    assert copy() == "completed"
    summary = json.loads((tmp_path / "run-0000" / "summary.json").read_text())
    assert summary["status"] == "completed" and summary["fps"] == 30
    assert copy() == "completed"  # a done run is not made again
