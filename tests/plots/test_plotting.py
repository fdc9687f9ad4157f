"""The trajectory figure and the animation write readable files for a short hunt."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from PIL import Image

from mpc_hunt import Attacker, Defender, HuntParameters, HuntResult, Obstacle, Scenario, simulate
from mpc_hunt.plots.animation import animate_hunt, frame_steps
from mpc_hunt.plots.hunt import FIGURE_DPI, FIGURE_SIZE, plot_hunt, predicted_path


@pytest.fixture(scope="module")
def short_hunt() -> tuple[HuntResult, Scenario]:
    """Two defenders and an obstacle; the hunt stops at its 20 s time limit (200 steps)."""
    scenario = Scenario(
        name="short-hunt",
        defenders=(Defender(start=(0.0, 0.0), max_speed=0.08), Defender(start=(3.0, 0.5), max_speed=0.08)),
        attacker=Attacker(start=(1.0, 1.5), nominal_velocity=(1.0, 0.0), max_speed=0.03,
                          perception_radius=1.0),
        obstacles=(Obstacle(centre=(2.0, 3.0), radius=0.5),),
        hunt=HuntParameters(time_limit=20.0),
    )
    return simulate(scenario), scenario


@pytest.mark.parametrize("captured", [False, True])
def test_plot_hunt_writes_a_png(short_hunt, tmp_path, captured):
    result, scenario = short_hunt
    path = tmp_path / "hunt.png"
    # captured=True also draws the final hunting circle
    plot_hunt(dataclasses.replace(result, captured=captured), scenario, path)
    assert path.stat().st_size > 0
    with Image.open(path) as image:
        assert image.format == "PNG"
        assert image.size == (round(FIGURE_SIZE[0] * FIGURE_DPI), round(FIGURE_SIZE[1] * FIGURE_DPI))


def test_animate_hunt_writes_a_gif_of_at_most_frames_frames(short_hunt, tmp_path):
    result, scenario = short_hunt
    path = tmp_path / "hunt.gif"
    animate_hunt(result, scenario, path, frames=12, fps=10)
    assert path.stat().st_size > 0
    with Image.open(path) as image:
        assert image.format == "GIF"
        assert 1 < image.n_frames <= 12


def test_animate_hunt_rejects_no_frames(short_hunt, tmp_path):
    result, scenario = short_hunt
    with pytest.raises(ValueError, match="frames"):
        animate_hunt(result, scenario, tmp_path / "hunt.gif", frames=0)


def test_frame_steps_span_the_whole_hunt():
    steps = frame_steps(1000, 120)
    assert steps[0] == 0 and steps[-1] == 1000 and len(steps) == 120
    assert list(frame_steps(3, 120)) == [0, 1, 2, 3]


def test_predicted_path_only_with_prediction(short_hunt):
    result, _ = short_hunt
    line = predicted_path(result)
    # Step 0 knows no attacker velocity; the first prediction is made at step 1, along its motion.
    assert line is not None and np.allclose(line[0], result.attacker[1])
    motion = result.attacker[1] - result.attacker[0]
    along = line[1] - line[0]
    assert abs(motion[0] * along[1] - motion[1] * along[0]) <= 1e-9 * np.linalg.norm(along)
    assert motion @ along > 0
    assert predicted_path(dataclasses.replace(result, controller={**result.controller, "prediction": False})) is None
