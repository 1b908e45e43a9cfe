"""load_scene(): built-in names, files, dicts and set=, with the command's checks and messages."""

import json

import pytest

import clothsim


def test_a_builtin_scene_loads_by_name_and_lists_with_the_others():
    scenes = clothsim.builtin_scenes()
    assert {"paper-fig4", "paper-fig5", "paper-fig6"} <= set(scenes)
    scene = clothsim.load_scene("paper-fig5")
    assert scene.name == "paper-fig5"
    assert scene.particles == scene.rows * scene.cols > 0
    assert scene.frames == round(scene.duration * scene.fps) + 1
    assert "paper-fig5" in repr(scene)


def test_set_applies_values_in_their_types_as_the_command_line_does():
    scene = clothsim.load_scene(
        "paper-fig5",
        set={
            "output.fps": 30,
            "output.duration": 2.5,
            "environment.gravity": [0.0, -3.5, 0.0],
            "integrator.method": "rk4",
            "integrator.time_step": 1e-4,
            "collision.self": True,
            "springs.connector.break_strain": None,
        },
    )
    document = scene.to_dict()
    assert document["output"]["fps"] == 30
    assert document["output"]["duration"] == 2.5
    assert document["environment"]["gravity"] == [0.0, -3.5, 0.0]
    assert document["integrator"]["method"] == "rk4"
    assert document["integrator"]["time_step"] == 1e-4
    assert document["collision"]["self"] is True
    assert scene.fps == 30 and scene.frames == 76


def test_a_dict_and_a_file_give_the_scene_they_hold(tmp_path):
    scene = clothsim.load_scene("paper-fig6", set={"output.fps": 24})
    document = scene.to_dict()
    assert clothsim.load_scene(document) == scene
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(document))
    assert clothsim.load_scene(path) == scene  # os.PathLike
    assert clothsim.load_scene(str(path)) == scene
    # A Scene is copied, and set= applies to the copy only.
    faster = clothsim.load_scene(scene, set={"output.fps": 48})
    assert faster.fps == 48 and scene.fps == 24


def test_a_bad_scene_raises_scene_error_naming_the_field(tmp_path):
    with pytest.raises(clothsim.SceneError) as error:
        clothsim.load_scene({"lattice": {"rows": 0, "cols": 5}})
    assert isinstance(error.value, ValueError)
    assert error.value.field == "lattice.rows"
    assert "field 'lattice.rows'" in str(error.value)
    assert "[1, 4096]" in str(error.value)

    path = tmp_path / "bad.json"
    path.write_text('{"output": {"fps": 2.5}}')
    with pytest.raises(clothsim.SceneError) as error:
        clothsim.load_scene(path)
    assert error.value.field == "output.fps"
    assert str(error.value).startswith(str(path) + ": field 'output.fps': ")


def test_set_errors_are_the_command_lines_with_set_as_their_source():
    with pytest.raises(clothsim.SceneError) as error:
        clothsim.load_scene("paper-fig5", set={"output.fps": 0})
    assert str(error.value) == "set: field 'output.fps': must be an integer in [1, 10000], got \"0\""
    assert (error.value.source, error.value.field) == ("set", "output.fps")
    with pytest.raises(clothsim.SceneError, match="no.such"):
        clothsim.load_scene("paper-fig5", set={"no.such": 1})
    # Cross-field rules are checked after the last value, as after the command's flags.
    with pytest.raises(clothsim.SceneError, match="paper-fig5 with set"):
        clothsim.load_scene("paper-fig5", set={"integrator.min_step": 0.5, "integrator.max_step": 0.1})


def test_an_unknown_name_says_it_is_neither_a_file_nor_a_builtin():
    with pytest.raises(clothsim.SceneError, match="not a built-in scene either"):
        clothsim.load_scene("paper-fig7")
    with pytest.raises(TypeError):
        clothsim.load_scene(42)


def test_the_registry_lists_every_key_set_takes_and_marks_the_live_ones():
    parameters = clothsim.parameters()
    assert parameters["output.fps"]["type"] == "integer"
    assert parameters["springs.connector.stiffness"]["unit"] == "N/m"
    live = clothsim.live_parameters()
    assert "springs.connector.stiffness" in live and "integrator.method" in live
    assert "lattice.rows" not in live
    assert all(parameters[key]["live"] for key in live if key in parameters)
