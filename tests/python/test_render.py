"""hairlod.render, hairlod.flip and the render command: metrics on synthetic cases, deterministic
small renders, images out, CLI contract. Renders are tiny (32 x 32, few spp) to keep the suite fast."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO

from hairlod import flip, io, lod, render


def run_cli(*args):
    env = dict(os.environ, PYTHONPATH=str(REPO / "addon"))
    return subprocess.run([sys.executable, "-m", "hairlod", *map(str, args)], capture_output=True, text=True, env=env,
                          timeout=300)


def _noise_image(seed, shape=(32, 32, 3)):
    return np.random.default_rng(seed).uniform(0.0, 1.0, shape)


def test_flip_identical_is_zero_and_symmetric():
    a, b = _noise_image(1), _noise_image(2)
    assert flip.flip(a, a) == pytest.approx(0.0, abs=1e-12)
    assert flip.flip(a, b) == pytest.approx(flip.flip(b, a), abs=1e-12)
    error = flip.flip_map(a, b)
    assert error.shape == (32, 32) and np.all((error >= 0.0) & (error <= 1.0))


def test_flip_grows_with_colour_difference():
    grey = np.full((24, 24, 3), 0.5)
    errors = []
    for delta in (0.02, 0.05, 0.1, 0.2, 0.4):
        shifted = grey.copy()
        shifted[8:16, 8:16, 0] += delta  # a red square of growing contrast
        errors.append(flip.flip(shifted, grey))
    assert all(b > a for a, b in zip(errors, errors[1:])), errors
    # A pure luminance step far larger than a slight tint must read as a larger error.
    assert flip.flip(np.zeros((24, 24, 3)), np.ones((24, 24, 3))) > flip.flip(grey, grey + 0.05)


def test_psnr_and_ssim():
    a = np.full((32, 32, 3), 0.3)
    assert render.psnr(a, a) == float("inf")
    assert render.ssim(a, a) == pytest.approx(1.0)
    b = a + np.random.default_rng(0).normal(0.0, 0.05, a.shape)
    c = a + np.random.default_rng(0).normal(0.0, 0.1, a.shape)
    assert render.psnr(b, a) > render.psnr(c, a) > 10.0
    assert render.ssim(b, a) > render.ssim(c, a)


def test_srgb_transfer_endpoints():
    out = render.to_srgb8(np.array([0.0, 0.0031308, 0.18, 1.0, 7.0]))
    assert out.tolist() == [0, 10, 118, 255, 255]


def test_render_is_deterministic_and_writes_images(shared_data, tmp_path):
    strands = io.read(shared_data / "Bangs_100.hair")
    a = render.render(strands, method="pt", view="near", width=32, spp=2, seed=3)
    b = render.render(strands, method="pt", view="near", width=32, spp=2, seed=3)
    assert a["image"].shape == (32, 32, 3) and np.array_equal(a["image"], b["image"])
    assert a["segments"] == strands.point_count - len(strands)  # one Catmull-Rom segment per point pair
    assert a["rays"] > 32 * 32 * 2 and a["rays_per_second"] > 0
    render.write_image(tmp_path / "x.exr", a["image"])
    render.write_image(tmp_path / "x.png", a["image"])
    import OpenImageIO as oiio

    back = oiio.ImageBuf(str(tmp_path / "x.exr")).get_pixels(oiio.FLOAT)
    assert np.array_equal(back.reshape(a["image"].shape), a["image"])
    assert sorted(os.listdir(tmp_path)) == ["x.exr", "x.png"]
    with pytest.raises(ValueError, match="x.jpg"):
        render.write_image(tmp_path / "x.jpg", a["image"])


def test_direct_light_alone_keeps_the_environments_bcsdf_sampled_share():
    # One strand alone under a white sky: nothing else to scatter from, so its direct light (max_bounces 0)
    # is all of its light (max_bounces 1), up to the two renders' noise (8 %: blue moves by 3-6 % from
    # seed to seed). Next-event estimation weights the sky by MIS against BCSDF sampling; stopped before
    # that sample, the strand read 0.16 of 0.66 in red.
    t = np.linspace(0.0, 1.0, 17)
    points = np.stack([0.3 * np.sin(1.5 * t), t, 0.1 * t], axis=1).astype(np.float32)
    strand = render._core.Strands(points, np.array([0, 17], np.int64), np.full(17, 0.02, np.float32))
    camera = render.frame_view(strand.points, "near", 32)
    sky = {"directional": [], "points": [], "environment": np.ones(3, np.float32)}
    alpha = 1.0 - render.render(strand, width=32, spp=256, camera=camera, coverage_only=True)["image"][..., 0]
    hair = alpha > 0.3
    assert hair.sum() >= 10
    means = [((render.render(strand, width=32, spp=512, camera=camera, max_bounces=bounces, lights=sky, seed=seed)["image"]
               - (1.0 - alpha)[..., None])[hair] / alpha[hair][:, None]).mean(axis=0)
             for bounces, seed in ((0, 1), (1, 2))]
    assert np.all(means[1] > 0.1)
    np.testing.assert_allclose(means[0], means[1], rtol=0.08)


def test_views_cover_decreasing_fractions(shared_data):
    strands = io.read(shared_data / "Bangs_100.hair")
    lights = {"directional": [], "points": [], "environment": np.zeros(3, np.float32)}
    covered = {}
    for view in ("near", "mid", "far"):
        # White hair against black, lit only by a uniform sky: covered pixels are the non-black ones.
        camera = render.frame_view(strands.points, view, 48)
        sky = dict(lights, environment=np.ones(3, np.float32))
        image = render.render(strands, method="pt", width=48, spp=1, camera=camera, max_bounces=0,
                              lights=sky)["image"]
        covered[view] = float(np.mean(image[..., 0] < 0.999))
    assert covered["near"] > covered["mid"] > covered["far"] and covered["mid"] > 0.0


def test_lod_methods_render_the_selection(shared_data):
    strands = io.read(shared_data / "Bangs_100.hair")
    asset = lod.build_lod(strands, guides=16, levels=3)
    results = {m: render.render(strands, method=m, view="far", width=32, spp=2, asset=asset)
               for m in ("lod", "lod-single", "lod-no-s")}
    for result in results.values():
        assert np.all(np.isfinite(result["image"])) and result["thick_segments"] > 0
    with pytest.raises(ValueError, match="LoD asset"):
        render.render(strands, method="lod", width=8, spp=1)
    # Paths scattering inside their own thick hair: the single fibre's option, refused elsewhere by name.
    scatter = render.render(strands, method="lod-single", view="far", width=32, spp=2, asset=asset, own_hair="scatter")
    assert np.all(np.isfinite(scatter["image"])) and scatter["thick_segments"] == results["lod-single"]["thick_segments"]
    with pytest.raises(ValueError, match="own_hair 'scatter' applies to the lod-single method only, not 'lod'"):
        render.render(strands, method="lod", width=8, spp=1, asset=asset, own_hair="scatter")
    with pytest.raises(ValueError, match="own_hair must be one of attenuate, scatter"):
        render.render(strands, method="lod-single", width=8, spp=1, asset=asset, own_hair="trace")


def test_cli_render(shared_data, tmp_path):
    out = tmp_path / "pt.png"
    done = run_cli("render", shared_data / "Bangs_100.hair", "--method", "ds", "--view", "mid", "--out", out,
                   "--spp", 2, "--width", 24, "--json")
    assert done.returncode == 0, done.stderr
    summary = json.loads(done.stdout)
    assert summary["output"] == str(out) and summary["segments"] > 0 and out.is_file()
    for bad, message in ((["--method", "lod"], "--lod"), (["--spp", "0"], "--spp"), (["--out", tmp_path / "a.tif"], "a.tif")):
        args = ["render", shared_data / "Bangs_100.hair", "--out", tmp_path / "b.png", *bad]
        done = run_cli(*args)
        assert done.returncode == 2 and message in done.stderr and len(done.stderr.strip().splitlines()) == 1
    assert sorted(os.listdir(tmp_path)) == ["pt.png"]
