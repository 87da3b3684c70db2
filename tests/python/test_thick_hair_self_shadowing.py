"""A thick hair against its own strands, by brute force: one bundle of strands placed at random in an
elliptical cross-section, rendered as the strands themselves (`pt`) and as the one thick hair that
stands for them (hair-lod-aggregated-bcsdf.txt Sec. 4). The renderer shades a thick hair at the first
strand its ray meets inside (a Poisson arrival at the hair's density) and shadows that strand through
the hair's other strands, with the empty corridor the camera ray found there taken into account.
Fixed seeds; tolerances stated per test. Never times."""

import numpy as np
import pytest

from hairlod import _core
from hairlod.hair_params import as_params

# rho = 100 * 0.005^2 / (0.4 * 0.2) = 0.031: the density of real clusters (the generated and the
# artist-made hair: median rho 0.015-0.02, the real mohawk 1e-3) and a mean free path of 0.21 in the
# cross-section, so a ray meets several strands across the hair.
STRANDS, STRAND_RADIUS, MAJOR, MINOR, LENGTH, POINTS = 100, 0.005, 0.4, 0.2, 2.0, 9
# Bundles averaged: each is one random arrangement (the same in every column of the image), whose lit
# strands vary a lot from one to the next.
BUNDLES = 24
CAMERA = {"eye": [0.0, -3.0, 0.0], "target": [0.0, 0.0, 0.0], "up": [0.0, 0.0, 1.0], "fov_y": 0.5, "width": 48,
          "height": 48}
# Black fibres (sigma_a 8: the fibre's forward transmission a_f is ~0, so a strand behind another is in
# full shadow, as the path tracer's shadow rays have it) and no bounces: the images then differ only
# in where the light reaches the strands the camera sees.
BLACK = {"sigma_a": [8.0, 8.0, 8.0]}


def _bundle(seed):
    """STRANDS straight strands along x through uniform random points of the ellipse (minor semi-axis
    along y, major along z): the strand centres the thick hair's Poisson model assumes."""
    rng = np.random.default_rng(seed)
    points = rng.uniform(-1.0, 1.0, (4 * STRANDS, 2))
    middle = points[(points ** 2).sum(axis=1) <= 1.0][:STRANDS] * [MINOR, MAJOR]
    x = np.linspace(-LENGTH / 2, LENGTH / 2, POINTS)
    points = np.concatenate([np.broadcast_to(x[None, :, None], (STRANDS, POINTS, 1)),
                             np.broadcast_to(middle[:, None, :], (STRANDS, POINTS, 2))], axis=-1)
    return _core.Strands.from_counts(np.ascontiguousarray(points.reshape(-1, 3), np.float32),
                                     np.full(STRANDS, POINTS, np.int64), np.full(STRANDS * POINTS, STRAND_RADIUS, np.float32))


def _thick_hair():
    """The thick hair of the bundles: Sec. 4's ellipse and rho (0.375: a dense cluster)."""
    x = np.linspace(-LENGTH / 2, LENGTH / 2, POINTS)
    return {"centres": np.stack([x, 0 * x, 0 * x], axis=-1).astype(np.float32),
            "major_axis": np.tile([0.0, 0.0, 1.0], (POINTS, 1)).astype(np.float32),
            "radii": np.tile([MAJOR, MINOR], (POINTS, 1)).astype(np.float32),
            "density": np.full(POINTS, STRANDS * STRAND_RADIUS ** 2 / (MAJOR * MINOR), np.float32),
            "offsets": np.array([0, POINTS], np.int64), "n_total": np.array([STRANDS], np.float32)}


def _sun(towards_light):
    direction = -np.asarray(towards_light, np.float64) / np.linalg.norm(towards_light)
    return {"directional": [(tuple(direction), (3.0, 3.0, 3.0))], "points": [],
            "environment": np.zeros(3, np.float32)}


@pytest.fixture(scope="module")
def bundles():
    return [_bundle(seed) for seed in range(BUNDLES)]


def _strands_mean(bundles, lights, params, **options):
    return np.mean([_core.render(strands, None, CAMERA, lights, params, method="pt", seed=1, **options)["image"]
                    for strands in bundles], axis=0)


@pytest.mark.parametrize("towards_light", [(0.0, -1.0, 1.0), (0.0, -0.3, 1.0), (0.0, 1.0, 1.0), (-0.5, 0.2, 1.0)],
                         ids=["camera-side", "above", "behind", "oblique"])
def test_thick_hair_shadows_itself_like_its_strands(bundles, towards_light):
    # The mean image of the single fibre on the thick hair within 6 % of its strands' (measured -2.3,
    # -2.7, +1.1 and -0.3 %). Shaded where the ray enters the tube and not shadowed by itself, the thick
    # hair was several times too bright lit from above or behind; with the strands on the light's path
    # taken as independent of the view (no shared corridor) it was too dark lit from the camera's side.
    # Denser clusters come out darker than their strands: -7 to -13 % at rho 0.094, -19 to -51 % at
    # rho 0.375 (the lit layer is then a few strand radii deep, where strips of width 2 r are rough).
    params, lights = as_params(BLACK), _sun(towards_light)
    expected = _strands_mean(bundles, lights, params, spp=32, max_bounces=0).mean()
    measured = _core.render(None, _thick_hair(), CAMERA, lights, params, method="lod-single", spp=128, max_bounces=0,
                            seed=2)["image"].mean()
    assert expected > 0
    assert abs(measured / expected - 1.0) < 0.06, (measured, expected)


def test_thick_hair_covers_like_its_strands(bundles):
    # Black hair under a white sky: the sky seen through the bundle. The thick hair's gaps (a Poisson
    # count of strands along each ray) let through what the strands let through: total alpha within 5 %
    # (measured -0.2 %).
    params = as_params(BLACK)
    sky = {"directional": [], "points": [], "environment": np.ones(3, np.float32)}
    alpha_strands = 1.0 - _strands_mean(bundles, sky, params, spp=16, coverage_only=True)[..., 0]
    alpha_thick = 1.0 - _core.render(None, _thick_hair(), CAMERA, sky, params, method="lod", spp=64, seed=2,
                                     coverage_only=True)["image"][..., 0]
    assert alpha_strands.sum() > 0
    assert abs(alpha_thick.sum() / alpha_strands.sum() - 1.0) < 0.05, (alpha_thick.sum(), alpha_strands.sum())


@pytest.mark.parametrize("towards_light", [(0.0, -1.0, 1.0), (0.0, 1.0, 1.0)], ids=["camera-side", "behind"])
def test_paths_scattering_inside_the_hair_light_it_like_its_strands(bundles, towards_light):
    # The default (brown) fibre and every bounce: light crosses strands and scatters between them. With
    # paths that meet the hair's own strands at their Poisson arrivals and scatter there (own_hair
    # "scatter"), the mean image per channel is within 5 % of its strands' (measured +2.1 / +0.9 /
    # -2.4 % lit from the camera's side, +2.2 / +2.1 / +0.7 % from behind). Skipping those strands and
    # keeping dual scattering's forward share (the default) drops the light they scatter back: 0.60 /
    # 0.78 / 0.93 of the strands' from the camera's side, 1.13 / 1.09 / 1.03 from behind, which is
    # reported, not asserted (docs/lod-quality.md).
    params, lights = as_params({}), _sun(towards_light)
    expected = _strands_mean(bundles, lights, params, spp=16).mean(axis=(0, 1))
    measured = _core.render(None, _thick_hair(), CAMERA, lights, params, method="lod-single", spp=128, seed=2,
                            own_hair="scatter")["image"].mean(axis=(0, 1))
    assert (expected > 0).all()
    np.testing.assert_allclose(measured / expected, 1.0, atol=0.05)


def test_scattering_inside_is_for_the_single_fibre_only():
    # The aggregated BCSDF already carries the strands behind its first (A_1+): tracing them too would
    # count them twice, so the renderer refuses it, naming the option.
    params, lights = as_params({}), _sun((0.0, -1.0, 1.0))
    with pytest.raises(Exception, match="own_hair 'scatter' applies to the lod-single method only"):
        _core.render(None, _thick_hair(), CAMERA, lights, params, method="lod", spp=1, own_hair="scatter")
    with pytest.raises(Exception, match="unknown own-hair treatment 'bounce'"):
        _core.render(None, _thick_hair(), CAMERA, lights, params, method="lod-single", spp=1, own_hair="bounce")
