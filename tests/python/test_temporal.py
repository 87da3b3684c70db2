"""hairlod.temporal: the LoD's temporal stability on animated hair (Embree renders per frame)."""

import math

import numpy as np
import pytest

from hairlod import Strands, lod, temporal
from test_lod import hanging_hair


@pytest.fixture(scope="module")
def hair():
    return hanging_hair(curves=800, points=10)


def moved(hair, angle):
    """The hair nodded by `angle` about the x axis (the hanging hair is round about z: a turn about z
    would barely change its image)."""
    c, s = math.cos(angle), math.sin(angle)
    rotation = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    return Strands((hair.points @ rotation.T).astype(np.float32), hair.offsets, hair.radius)


def test_still_frames_read_as_identical_and_motion_does_not(hair):
    asset = lod.build_lod(hair, guides=12, levels=4, control_points=8, seed=1)
    still = temporal.bench_animation([hair, hair], asset=asset, width=32, spp=2)
    assert still["frames"] == 2 and len(still["rows"]) == 2
    # The same seed every frame: a hair that does not move gives the same image, LoD and strands alike
    # (an infinite PSNR, stored as None: strict JSON has no Infinity).
    assert still["rows"][1]["strands_adjacent_psnr"] is None and still["rows"][1]["lod_adjacent_psnr"] is None
    assert still["adjacent_psnr_gap_db"] is None
    moving = temporal.bench_animation([moved(hair, a) for a in (0.0, 0.15, 0.3)], asset=asset, width=32, spp=2)
    for row in moving["rows"][1:]:
        assert row["strands_adjacent_psnr"] > 0.0 and row["lod_adjacent_psnr"] > 0.0
    assert moving["adjacent_psnr_gap_db"] == pytest.approx(moving["mean_lod_adjacent_psnr"] -
                                                           moving["mean_strands_adjacent_psnr"])
    assert all(row["lod_segments"] > 0 and row["strand_segments"] > 0 for row in moving["rows"])
    assert 0 < moving["hair_box"][0] <= 32 and moving["hair_box"][0] % 4 == 0


def test_lod_frames_follow_the_hair(hair):
    """The LoD skinned to a turned frame's guides renders much closer to the turned strands than the
    rest-pose LoD does (render(guides=...), what bench_animation renders each frame)."""
    from hairlod import render

    asset = lod.build_lod(hair, guides=12, levels=4, control_points=8, seed=1)
    turned = moved(hair, 0.5)
    # The near view: at mid the hair covers about 10 of the 48 px and a few noisy pixels of the 16-spp
    # images move the followed image's blurred PSNR by up to 6 dB (49-56 dB over build seeds, the stale
    # image 47-50). Near, the followed image is 51-54 dB against the stale 42-43 over build seeds and
    # thick-hair fits.
    camera = render.frame_view(hair.points, "near", 48)
    truth = render.render(turned, "pt", width=48, spp=16, camera=camera)["image"]
    stale = render.render(turned, "lod", width=48, spp=16, asset=asset, camera=camera)["image"]
    followed = render.render(turned, "lod", width=48, spp=16, asset=asset, camera=camera,
                             guides=lod.frame_guides(asset, turned))["image"]
    assert render.blurred_psnr(followed, truth) > render.blurred_psnr(stale, truth) + 6.0


def test_bad_animations_are_refused(hair):
    with pytest.raises(ValueError, match="at least 2 frames"):
        temporal.bench_animation([hair])
    asset = lod.build_lod(hair, guides=12, levels=4, control_points=8, seed=1)
    with pytest.raises(ValueError, match="frame 1 has 5 curves, the LoD asset 800"):
        temporal.bench_animation([hair, hanging_hair(curves=5, points=10)], asset=asset, width=32, spp=1)
