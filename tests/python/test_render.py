"""Simulation.render(): a headless picture as a NumPy image."""

import numpy
import pytest

import clothsim
from conftest import short_scene

pytestmark = pytest.mark.skipif(not clothsim.has_render, reason="built without CLOTHSIM_BUILD_RENDER")


def test_render_gives_a_top_down_rgb_image_of_the_sheet():
    simulation = clothsim.Simulation(short_scene("paper-fig5", 1.0))
    simulation.advance_to(0.5)
    image = simulation.render(160, 120, samples=1)
    assert image.shape == (120, 160, 3) and image.dtype == numpy.uint8
    # The background (light grey-blue) fills the top row; the sheet (terracotta and blue) and the
    # ground are drawn too: many distinct colours, not a blank image.
    assert numpy.all(image[0, :, :] > 200)
    assert len(numpy.unique(image.reshape(-1, 3), axis=0)) > 20
    reddish = (image[:, :, 0].astype(int) - image[:, :, 2]) > 60
    assert reddish.sum() > 50, "the sheet's front (terracotta) is in the picture"


def test_render_follows_the_simulation_and_takes_the_commands_settings():
    simulation = clothsim.Simulation(short_scene("paper-fig5", 1.0))
    first = simulation.render(96, 64, samples=1)
    simulation.advance_to(0.5)
    second = simulation.render(96, 64, samples=1)
    assert not numpy.array_equal(first, second)
    wire = simulation.render(96, 64, samples=1, show="wireframe")
    assert not numpy.array_equal(second, wire)
    with pytest.raises(clothsim.SceneError, match="--size"):
        simulation.render(4, 4)
    with pytest.raises(clothsim.SceneError, match="--show"):
        simulation.render(64, 64, show="sparkles")
