"""bench quality (hairlod.quality, its metrics in hairlod.render, and the CLI) on a tiny input: JSON
structure and invariants; never times."""

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO

from hairlod import _core, bench, io, lod, quality, render


def run_cli(*args):
    env = dict(os.environ, PYTHONPATH=str(REPO / "addon"))
    return subprocess.run([sys.executable, "-m", "hairlod", *map(str, args)], capture_output=True, text=True, env=env,
                          timeout=600)


@pytest.fixture(scope="module")
def tiny_hair(tmp_path_factory):
    path = tmp_path_factory.mktemp("quality") / "tiny.hair"
    # 16 points: the LoD stores strands at its 16 control points, so its finest level draws as many
    # segments as the input (fewer input points would make the strand level cost more than the input).
    io.write(str(path), bench.synthetic_hair(300, 16))
    return path


@pytest.fixture(scope="module")
def tiny_strands(tiny_hair):
    return io.read(str(tiny_hair))


def test_box_average_of_a_constant_is_the_constant():
    image = np.full((18, 13, 3), 0.37)
    averaged = render.box_average(image, 4)
    # Rows and columns past the last whole block are dropped.
    assert averaged.shape == (4, 3, 3) and np.allclose(averaged, 0.37, rtol=0, atol=1e-15)
    ramp = np.arange(16.0).reshape(4, 4)
    assert render.box_average(ramp, 2).tolist() == [[2.5, 4.5], [10.5, 12.5]]
    with pytest.raises(ValueError, match="block"):
        render.box_average(np.zeros((3, 8, 3)), 4)


def test_blurred_psnr_reads_bias_not_noise():
    clean = np.full((64, 64, 3), 0.3)
    assert render.blurred_psnr(clean, clean) == math.inf
    noisy = clean + np.random.default_rng(5).normal(0.0, 0.05, clean.shape)  # the same mean, pixel noise
    # 4 x 4 averages cut the noise's standard deviation 4 times: about +12 dB.
    assert render.blurred_psnr(noisy, clean) > render.psnr(noisy, clean) + 8.0
    biased = clean * 1.1  # a bias: no averaging removes it
    assert abs(render.blurred_psnr(biased, clean) - render.psnr(biased, clean)) < 0.5


def test_mean_radiance_error():
    rng = np.random.default_rng(2)
    reference = rng.uniform(0.1, 1.0, (16, 16, 3))
    hair = np.zeros((16, 16), bool)
    hair[4:12, 2:9] = True
    assert render.mean_radiance_error(reference, reference, hair).tolist() == [0.0, 0.0, 0.0]
    scaled = reference * np.array([1.1, 1.0, 0.5])
    assert np.allclose(render.mean_radiance_error(scaled, reference, hair), [0.1, 0.0, -0.5], rtol=0, atol=1e-12)
    # Only the hair's pixels count.
    scaled[~hair] = 7.0
    assert np.allclose(render.mean_radiance_error(scaled, reference, hair), [0.1, 0.0, -0.5], rtol=0, atol=1e-12)
    assert np.isnan(render.mean_radiance_error(scaled, reference, np.zeros_like(hair))).all()
    black = reference.copy()
    black[..., 2] = 0.0
    assert np.isnan(render.mean_radiance_error(black, black, hair)).tolist() == [False, False, True]


def test_weighted_percentiles():
    values = np.array([3.0, 1.0, 2.0, 100.0])
    # Equal weights: the cumulative distribution through the sorted values, linear between them.
    assert render.weighted_percentiles(values[:3], np.ones(3), (100 / 3, 200 / 3, 100)).tolist() == \
        pytest.approx([1.0, 2.0, 3.0])
    # A value of weight 0 moves nothing, and one of small weight little (a noisy, barely covered pixel).
    assert render.weighted_percentiles(values, [1, 1, 1, 0], (5, 95)).tolist() == \
        render.weighted_percentiles(values[:3], np.ones(3), (5, 95)).tolist()
    assert render.weighted_percentiles(values, [1, 1, 1, 1e-3], (95,))[0] < 3.1
    # Only the weights' proportions count; a heavier value pulls the percentiles towards it.
    assert render.weighted_percentiles(values, [0.5, 0.5, 0.5, 0.5], (30, 50, 80)) == pytest.approx(
        render.weighted_percentiles(values, [3, 3, 3, 3], (30, 50, 80)))
    assert render.weighted_percentiles(values[:3], [8, 1, 1], (50,))[0] > render.weighted_percentiles(
        values[:3], [1, 1, 1], (50,))[0]
    for weights, match in (([1, 1], "values"), ([1, -1, 1, 1], ">= 0"), ([0, 0, 0, 0], "positive")):
        with pytest.raises(ValueError, match=match):
            render.weighted_percentiles(values, weights, (50,))


def test_same_pixels_spread_compares_the_same_pixels():
    rng = np.random.default_rng(4)
    reference = rng.uniform(0.01, 0.1, (24, 30, 3))
    coverage = np.ones((24, 30))
    # An image at twice the resolution whose hair pixels hold the reference's radiance, a quarter of
    # them left as sky (their value must not count): the same spread on the reference's pixels.
    image = np.repeat(np.repeat(reference, 2, axis=0), 2, axis=1)
    hair = np.ones(image.shape[:2], bool)
    hair[::2, ::2] = False
    image[~hair] = 5.0
    spread = render.same_pixels_spread(image, hair, reference, coverage, 2)
    assert spread["pixels"] == 24 * 30 and spread["ratio"] == pytest.approx(1.0)
    assert spread["image"] == pytest.approx(spread["reference"])
    # Pixels the reference covers barely (noise over a small coverage when unmixed) do not count.
    noisy, barely = reference.copy(), coverage.copy()
    noisy[:3] = 50.0
    barely[:3] = 0.1
    assert render.same_pixels_spread(image, hair, noisy, barely, 2)["reference"] == pytest.approx(
        render.same_pixels_spread(image[6:], hair[6:], reference[3:], coverage[3:], 2)["reference"])
    # Twice the contrast about the same mean: twice the spread.
    mean = reference.mean(axis=(0, 1))
    contrasted = np.repeat(np.repeat(mean + 2.0 * (reference - mean), 2, axis=0), 2, axis=1)
    assert render.same_pixels_spread(contrasted, hair, reference, coverage, 2)["ratio"] == pytest.approx(2.0)
    # Too few pixels covered by both: no spread.
    little = np.zeros_like(coverage)
    little[0, :render.SPREAD_LEAST_PIXELS - 1] = 1.0
    assert render.same_pixels_spread(image, hair, reference, little, 2) is None


def test_same_pixels_rows_follow_the_shading_from_row_to_row():
    # A reference brightening row by row (roots to tips), and an image at twice its resolution: holding
    # the same radiance it reads the same bands; flat at the reference's mean it reads flat bands.
    rows = np.linspace(0.2, 0.5, 24)
    reference = np.repeat(rows[:, None, None], 30, axis=1) * np.ones(3)
    coverage = np.ones((24, 30))
    hair = np.ones((48, 60), bool)
    same = render.same_pixels_rows(np.repeat(np.repeat(reference, 2, axis=0), 2, axis=1), hair, reference, coverage, 2)
    assert same["pixels"] == 24 * 30 and len(same["image"]) == 6
    np.testing.assert_allclose(same["image"], same["reference"], rtol=1e-12)
    assert np.all(np.diff(same["reference"]) > 0.0)
    np.testing.assert_allclose(same["reference"], rows.reshape(6, 4).mean(axis=1), rtol=1e-12)
    flat = np.full((48, 60, 3), reference.mean())
    bands = render.same_pixels_rows(flat, hair, reference, coverage, 2, bands=3)
    np.testing.assert_allclose(bands["image"], reference.mean(), rtol=1e-12)
    assert bands["reference"][2] / bands["reference"][0] == pytest.approx(rows[16:].mean() / rows[:8].mean())
    # Only the rows that hold pixels both cover are split into bands.
    coverage[:12] = 0.0
    upper = render.same_pixels_rows(np.repeat(np.repeat(reference, 2, axis=0), 2, axis=1), hair, reference, coverage, 2,
                                    bands=2)
    np.testing.assert_allclose(upper["reference"], [rows[12:18].mean(), rows[18:].mean()], rtol=1e-12)
    assert render.same_pixels_rows(flat, hair, reference, np.zeros_like(coverage), 2) is None
    with pytest.raises(ValueError, match="bands"):
        render.same_pixels_rows(flat, hair, reference, coverage, 2, bands=0)


def test_hair_radiance_error_leaves_coverage_out():
    # Hair of radiance L over a sky of radiance S: a pixel covered by alpha shows alpha L + (1 - alpha) S.
    rng = np.random.default_rng(5)
    sky = np.array([0.15, 0.2, 0.3])
    hair_radiance = rng.uniform(0.01, 0.05, (16, 16, 3))
    reference_alpha = rng.uniform(0.3, 1.0, (16, 16))
    hair = reference_alpha > 0.5

    def shown(radiance, alpha):
        return alpha[..., None] * radiance + (1.0 - alpha[..., None]) * sky

    reference = shown(hair_radiance, reference_alpha)
    # The same hair with 10 % less coverage: the mixed mean moves towards the bright sky, the hair does not.
    thinner = 0.9 * reference_alpha
    assert np.all(render.mean_radiance_error(shown(hair_radiance, thinner), reference, hair) > 0.05)
    assert np.allclose(render.hair_radiance_error(shown(hair_radiance, thinner), thinner, reference, reference_alpha,
                                                  hair, sky), 0.0, rtol=0, atol=1e-12)
    # Hair 20 % redder and 10 % darker in blue under the reference's coverage: exactly that, per channel,
    # whatever the coverage (the error of the coverage-weighted mean hair radiance).
    tinted = hair_radiance * np.array([1.2, 1.0, 0.9])
    for alpha in (reference_alpha, thinner):
        error = render.hair_radiance_error(shown(tinted, alpha), alpha, reference, reference_alpha, hair, sky)
        truth = (alpha[hair][:, None] * tinted[hair]).sum(0) / alpha[hair].sum()
        expected = truth / ((reference_alpha[hair][:, None] * hair_radiance[hair]).sum(0) / reference_alpha[hair].sum()) - 1
        assert np.allclose(error, expected, rtol=0, atol=1e-12)
    assert np.allclose(render.hair_radiance_error(shown(tinted, reference_alpha), reference_alpha, reference,
                                                  reference_alpha, hair, sky), [0.2, 0.0, -0.1], rtol=0, atol=1e-12)
    # Nothing covered, or no hair pixels: NaN.
    assert np.isnan(render.hair_radiance_error(reference, np.zeros_like(thinner), reference, reference_alpha, hair,
                                               sky)).all()
    assert np.isnan(render.hair_radiance_error(reference, thinner, reference, reference_alpha, np.zeros_like(hair),
                                               sky)).all()


def test_coverage_error():
    alpha = np.random.default_rng(3).uniform(0.0, 1.0, (8, 8))
    assert render.coverage_error(alpha, alpha) == (0.0, 0.0)
    relative, mean_abs = render.coverage_error(alpha / 2, alpha)
    assert relative == pytest.approx(-0.5) and mean_abs == pytest.approx(np.mean(alpha) / 2)
    relative, mean_abs = render.coverage_error(alpha, np.zeros_like(alpha))
    assert math.isnan(relative) and mean_abs == pytest.approx(np.mean(alpha))


def test_coverage_of_an_empty_scene_is_zero(tiny_strands):
    camera = render.frame_view(tiny_strands.points, "near", 16)
    empty = _core.Strands.from_counts(np.zeros((0, 3), np.float32), np.zeros(0, np.int64), np.zeros(0, np.float32))
    alpha = render.coverage(empty, "pt", width=16, spp=2, camera=camera)
    assert alpha.shape == (16, 16) and not alpha.any()


def test_coverage_is_one_minus_the_coverage_only_image(tiny_strands):
    image = render.render(tiny_strands, "pt", "near", 24, 4, seed=9, coverage_only=True)["image"]
    # Black hair under a white environment: every channel is 1 - alpha, in [0, 1].
    assert np.array_equal(image[..., 0], image[..., 1]) and np.array_equal(image[..., 0], image[..., 2])
    alpha = render.coverage(tiny_strands, "pt", "near", 24, 4, seed=9)
    assert np.array_equal(alpha, 1.0 - image[..., 0])
    assert alpha.min() == 0.0 and 0.0 < alpha.max() <= 1.0
    # Coverage is the geometry's: ds draws the strands as pt does, and the same seed reads exactly 0.
    assert np.array_equal(render.coverage(tiny_strands, "ds", "near", 24, 4, seed=9), alpha)
    assert render.coverage_error(render.coverage(tiny_strands, "pt", "near", 24, 4, seed=9), alpha) == (0.0, 0.0)
    asset = lod.build_lod(tiny_strands, guides=20)
    # 16 spp: the far view's hair covers under one pixel's worth of the 24 x 24 image.
    thick = render.coverage(tiny_strands, "lod", "far", 24, 16, asset=asset, seed=9)
    assert 0.0 <= thick.min() and thick.max() <= 1.0 and thick.any()
    assert np.array_equal(render.coverage(tiny_strands, "lod-no-s", "far", 24, 16, asset=asset, seed=9), thick)
    with pytest.raises(ValueError, match="lights"):
        render.render(tiny_strands, "pt", "near", 16, 1, coverage_only=True, lights=render.default_lights(
            render.frame_view(tiny_strands.points, "near", 16)))


def test_image_window_holds_the_hair():
    reference = np.full((64, 48, 3), 0.15)
    other = reference.copy()
    other[40:45, 3:6] = 0.5  # the hair, near the left edge
    top, left, side = quality._hair_window(reference, [other])
    assert 8 <= side <= 48 and 0 <= top <= 40 and top + side >= 45 and left == 0 and left + side >= 6
    assert quality._hair_window(reference, [reference.copy()]) == (0, 0, 48)




def _finite_or_none(value, low=-math.inf):
    return value is None or low < value < math.inf


def test_bench_quality_cli_json_plot_and_images(tiny_hair, tmp_path):
    plot, images = tmp_path / "q.png", tmp_path / "images"
    images.mkdir()
    (images / "notes.txt").write_text("the user's own file")
    run = run_cli("bench", "quality", tiny_hair, "--json", "--width", 32, "--spp", 4, "--reference-spp", 8,
                  "--equal-time-spp", 2, "--eps-w", "1,4", "--plot", plot, "--images", images)
    assert run.returncode == 0, run.stderr
    result = json.loads(run.stdout, parse_constant=lambda name: pytest.fail(f"{name} in the JSON"))
    assert result["component"] == "quality" and result["strands"] == 300
    assert (result["width"], result["spp"], result["reference_spp"], result["equal_time"]["spp"]) == (32, 4, 8, 2)
    assert result["blur_box"] == 4 and result["hair_alpha"] == 0.5 and result["bench_seconds"] > 0
    assert result["lod_build"]["guides"] == result["guides"] == _core.auto_guide_count(300)
    assert set(result["views"]) == set(render.VIEWS) == set(result["equal_time"]["views"])
    for view, entry in result["views"].items():
        # The reference is not compared with itself: it has no error fields, and no row repeats it.
        reference = entry["reference"]
        assert "flip" not in reference and "blurred_psnr" not in reference
        assert 0.0 < reference["alpha_mean"] < 1.0 and 0 <= reference["hair_pixels"] <= 32 * 32
        assert (reference["hair_radiance"] is None) == (reference["hair_pixels"] == 0)
        assert set(entry["rows"]) == set(render.METHODS) == set(result["equal_time"]["views"][view]["rows"])
        for method, row in entry["rows"].items():
            assert 0.0 <= row["flip"] <= 1.0, (view, method)
            # PSNR is null (not Infinity, which is not JSON) when the 8-bit images are identical.
            assert -1.0 <= row["ssim"] <= 1.0 and _finite_or_none(row["psnr"], 0) and _finite_or_none(row["blurred_psnr"], 0)
            assert len(row["radiance_error"]) == 3 and all(_finite_or_none(v, -1.0) for v in row["radiance_error"])
            assert all(v is None for v in row["radiance_error"]) == (reference["hair_pixels"] == 0)
            assert _finite_or_none(row["coverage_error"], -1.0) and 0.0 <= row["coverage_abs_error"] <= 1.0
            assert row["segments"] == row["strand_segments"] + row["thick_segments"] > 0
            assert row["rays"] > 0 and row["rays_per_second"] > 0
        for method, row in result["equal_time"]["views"][view]["rows"].items():
            assert 0.0 <= row["flip"] <= 1.0 and len(row["radiance_error"]) == 3 and "coverage_error" not in row
            assert row["segments"] == entry["rows"][method]["segments"]
        # The strands' geometry, traced with the coverage renders' one seed: exactly the reference's coverage.
        for method in ("pt", "ds"):
            assert entry["rows"][method]["coverage_error"] == entry["rows"][method]["coverage_abs_error"] == 0.0
        full = entry["rows"]["pt"]["segments"]
        assert entry["rows"]["ds"]["segments"] == full == entry["reference"]["segments"]
        assert entry["rows"]["pt"]["thick_segments"] == 0
        assert result["summary"][view]["noise_floor_blurred_psnr"] == entry["rows"]["pt"]["blurred_psnr"]
    far = result["views"]["far"]["rows"]
    assert far["lod"]["segments"] <= far["pt"]["segments"]
    assert far["lod"]["segments"] == far["lod-single"]["segments"] == far["lod-no-s"]["segments"]
    assert far["lod"]["coverage_error"] == far["lod-single"]["coverage_error"] == far["lod-no-s"]["coverage_error"]
    assert result["summary"]["far"]["segment_reduction"] >= 1.0
    sweep = result["sweep"]
    assert sweep["view"] == "mid" and sweep["spp"] == 4 and [r["eps_w"] for r in sweep["rows"]] == [1.0, 4.0]
    # A coarser threshold never draws more segments.
    assert sweep["rows"][1]["segments"] <= sweep["rows"][0]["segments"] <= sweep["full_segments"]
    assert all(0.0 <= r["flip"] <= 1.0 and _finite_or_none(r["blurred_psnr"], 0) for r in sweep["rows"])
    assert result["plot"] == str(plot) and plot.stat().st_size > 1000
    assert sorted(os.listdir(tmp_path)) == ["images", "q.png"]
    # One PNG per view, each panel at least 256 px (32 px renders upscaled 8 times), the user's file untouched.
    assert result["images"] == [str(images / f"{view}.png") for view in render.VIEWS]
    assert sorted(os.listdir(images)) == ["far.png", "mid.png", "near.png", "notes.txt"]
    assert (images / "notes.txt").read_text() == "the user's own file"
    import matplotlib.image

    for view in render.VIEWS:
        height, width = matplotlib.image.imread(str(images / f"{view}.png")).shape[:2]
        panels = 1 + len(quality.IMAGE_METHODS) + 1  # the reference, the methods, the error map
        assert height >= quality.PANEL_PIXELS and width >= panels * quality.PANEL_PIXELS


def test_bench_quality_tables(tiny_strands):
    result = quality.bench_quality(tiny_strands, views=("far",), methods=("pt", "lod"), spp=2, width=16,
                                   reference_spp=4, equal_time_spp=1, eps_w=(2.0,), sweep_view="far", guides=20,
                                   keep_images=True)
    assert set(result["images"]["far"]) == {"reference", "pt", "lod"}
    tables = quality.format_tables(result)
    assert "| far | pt (noise floor, 2 spp) |" in tables and "| far | pt (noise floor, 1 spp) |" in tables
    assert "blurred PSNR dB" in tables and "radiance R / G / B %" in tables and "coverage %" in tables
    assert "hair alone R / G / B %" in tables
    assert all(len(row["hair_radiance_error"]) == 3 for row in result["views"]["far"]["rows"].values())
    blocks = [block.splitlines() for block in tables.split("\n\n") if block.startswith("|")]
    assert len(blocks) == 3  # converged, equal time, eps_w sweep
    for block in blocks:
        assert len({line.count("|") for line in block}) == 1, block  # every row has its header's columns


def test_view_spp_scales_equalise_the_hair_samples():
    # The power of two nearest the largest count over each view's, capped; a view without hair stays.
    assert quality.view_spp_scales({"near": 2600, "mid": 850, "far": 85}) == {"near": 1, "mid": 4, "far": 16}
    assert quality.view_spp_scales({"near": 2600, "mid": 850, "far": 85}, most=8) == {"near": 1, "mid": 4, "far": 8}
    assert quality.view_spp_scales({"near": 100, "far": 0}, most=1) == {"near": 1, "far": 1}
    assert quality.view_spp_scales({"near": 100, "far": 0}) == {"near": 1, "far": 1}
    with pytest.raises(ValueError, match="largest view spp scale"):
        quality.view_spp_scales({"near": 1}, most=0)


def test_bench_quality_renders_views_with_fewer_hair_pixels_at_more_spp(tiny_strands):
    def run(most):
        return quality.bench_quality(tiny_strands, views=("near", "mid"), methods=("pt",), spp=1, width=32,
                                     reference_spp=2, equal_time_spp=1, eps_w=(2.0,), sweep_view="mid", guides=20,
                                     max_view_spp_scale=most)
    result = run(quality.MAX_VIEW_SPP_SCALE)
    near, mid = result["views"]["near"], result["views"]["mid"]
    scales = quality.view_spp_scales({"near": near["reference"]["hair_pixels"], "mid": mid["reference"]["hair_pixels"]})
    assert near["reference"]["hair_pixels"] > 2 * mid["reference"]["hair_pixels"] > 0 and scales["mid"] > 1
    assert (near["spp"], near["reference_spp"]) == (scales["near"], 2 * scales["near"])
    assert (mid["spp"], mid["reference_spp"]) == (scales["mid"], 2 * scales["mid"]) and result["sweep"]["spp"] == mid["spp"]
    assert result["equal_time"]["spp"] == 1
    tables = quality.format_tables(result)
    assert f"| mid | pt (noise floor, {scales['mid']} spp) |" in tables
    assert f"| mid | pt reference ({2 * scales['mid']} spp) |" in tables
    plain = run(1)
    assert plain["views"]["mid"]["spp"] == 1 and plain["views"]["mid"]["reference_spp"] == 2
    with pytest.raises(ValueError, match="max view spp scale"):
        run(0)


def test_bench_quality_separates_direct_from_multiple_scattering():
    """With paths of 0 bounces every render, the reference's too, shows direct light only: on dense
    hair less light in every channel than with one more scattering, and that less than with all of
    them (measured +28 / +10 / +1 % from 0 to 70 bounces), and the tables say so."""
    from hairlod import generate_strands, hairmesh

    dense = generate_strands(hairmesh.read(os.path.join(REPO, "examples", "data", "wavy_cap.hairmesh.json")),
                             count=3000, vertices=9, seed=1)

    def run(bounces):
        return quality.bench_quality(dense, views=("mid",), methods=("pt",), spp=4, width=16, reference_spp=16,
                                     equal_time_spp=1, eps_w=(2.0,), sweep_view="mid", guides=20, max_bounces=bounces)
    direct, once, full = run(0), run(1), run(render.MAX_BOUNCES)
    assert direct["max_bounces"] == 0 and full["max_bounces"] == render.MAX_BOUNCES
    radiance = [np.array(result["views"]["mid"]["reference"]["hair_radiance"]) for result in (direct, once, full)]
    assert (radiance[0] < radiance[1]).all() and (radiance[1] < radiance[2]).all(), radiance
    assert "direct light only (paths of 0 bounces)." in quality.format_tables(direct)
    assert "paths of at most 1 bounce after" in quality.format_tables(once)
    assert "bounce" not in quality.format_tables(full).splitlines()[0]
    with pytest.raises(ValueError, match="max bounces"):
        run(-1)


def test_bench_quality_own_hair_changes_only_the_single_fibre_rows(tiny_strands):
    """`own_hair` reaches the lod-single renders (their images change with it), not the others, and
    the result and the tables say which was used."""
    def run(own_hair):
        return quality.bench_quality(tiny_strands, views=("mid",), methods=("lod", "lod-single"), spp=2, width=16,
                                     reference_spp=2, equal_time_spp=1, eps_w=(2.0,), sweep_view="mid", guides=20,
                                     keep_images=True, own_hair=own_hair)
    default, scatter = run(None), run("scatter")
    assert default["own_hair"] == "attenuate" and scatter["own_hair"] == "scatter"
    np.testing.assert_array_equal(default["images"]["mid"]["lod"], scatter["images"]["mid"]["lod"])
    assert not np.array_equal(default["images"]["mid"]["lod-single"], scatter["images"]["mid"]["lod-single"])
    assert "lod-single with own-hair scatter" in quality.format_tables(scatter).splitlines()[0]
    assert "own-hair" not in quality.format_tables(default).splitlines()[0]
    with pytest.raises(ValueError, match="own_hair must be one of attenuate, scatter"):
        run("bounce")


def test_bench_quality_vertex_tolerance_reaches_the_lod_rows_and_the_heading(tiny_strands):
    """The vertex LoD's tolerance reaches the lod renders (0 draws every control point: more segments
    at the near view), not pt, and the tables' heading says when it is not the default."""
    def run(tolerance):
        return quality.bench_quality(tiny_strands, views=("near",), methods=("pt", "lod"), spp=1, width=16,
                                     reference_spp=1, equal_time_spp=1, eps_w=(2.0,), sweep_view="near", guides=20,
                                     vertex_tolerance_px=tolerance)
    default, every = run(lod.DEFAULT_VERTEX_TOLERANCE_PX), run(0.0)
    rows, every_rows = default["views"]["near"]["rows"], every["views"]["near"]["rows"]
    assert rows["pt"]["segments"] == every_rows["pt"]["segments"]
    assert rows["lod"]["segments"] < every_rows["lod"]["segments"]
    assert default["vertex_tolerance_px"] == pytest.approx(lod.DEFAULT_VERTEX_TOLERANCE_PX)
    assert "vertex LoD" not in quality.format_tables(default).splitlines()[0]
    assert "every control point drawn" in quality.format_tables(every).splitlines()[0]
    assert "vertex LoD within 0.5 px" in quality.format_tables(run(0.5)).splitlines()[0]


def test_bench_quality_images_refuses_a_folder_in_the_way(tiny_hair, tmp_path):
    (tmp_path / "mid.png").mkdir()
    run = run_cli("bench", "quality", tiny_hair, "--width", 16, "--spp", 1, "--images", tmp_path)
    assert run.returncode == 2 and f"{tmp_path / 'mid.png'} is a folder" in run.stderr and run.stdout == ""
    assert len(run.stderr.strip().splitlines()) == 1 and os.listdir(tmp_path) == ["mid.png"]


@pytest.mark.parametrize("args, needle", [
    ((), "input hair file"),
    (("{hair}", "--spp", "0"), "--spp"),
    (("{hair}", "--reference-spp", "0"), "--reference-spp"),
    (("{hair}", "--equal-time-spp", "0"), "--equal-time-spp"),
    (("{hair}", "--width", "3"), "--width"),
    (("{hair}", "--max-bounces", "-1"), "--max-bounces"),
    (("{hair}", "--own-hair", "bounce"), "--own-hair"),
    (("{hair}", "--images", "{hair}"), "--images"),
    (("{hair}", "--images", "{hair}/sub"), "--images"),
    (("{hair}", "--eps-w", "1,x"), "--eps-w"),
    (("{hair}", "--plot", "out.jpg"), "out.jpg"),
    (("missing.hair",), "missing.hair"),
])
def test_bench_quality_bad_input(tiny_hair, args, needle):
    run = run_cli("bench", "quality", *[str(a).format(hair=tiny_hair) for a in args], "--json")
    assert run.returncode == 2 and needle in run.stderr and run.stdout == ""
    assert len(run.stderr.strip().splitlines()) == 1 and "Traceback" not in run.stderr
