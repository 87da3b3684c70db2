"""The LoD against the strands it replaces, on a real hairstyle (Ratboy_mohawk.tfx): the hierarchy's
shape (Sec. 5.1), the thick hairs' coverage against their own strands, and the mean hair radiance on
low-noise renders. Fixed seeds; tolerances stated per test. Never times."""

from pathlib import Path

import numpy as np
import pytest

from hairlod import lod, render


@pytest.fixture(scope="module")
def asset(real_hair):
    return lod.build_lod(real_hair)


def test_hierarchy_fits_the_real_hair(real_hair, asset):
    # Automatic guides: L0 clusters of tens of strands (256 guides made clusters of 3 here), thick levels
    # about 4x apart in cross-section area, and an asset at most half the strands' bytes.
    assert asset.guide_count == 2228 // 128
    assert np.mean(asset.levels[0].n_total) >= 20
    assert len(asset.levels) >= 2
    assert all(3.0 <= ratio <= 6.0 for ratio in asset.area_ratios), asset.area_ratios
    assert asset.memory_bytes <= 0.5 * lod.strand_bytes(real_hair)
    assert asset.stored_bytes <= 0.3 * lod.strand_bytes(real_hair)  # measured 0.22


def test_a_dense_hairs_asset_stores_under_half_the_strands_bytes():
    # 20,000 generated wavy strands of 17 points (272 bytes each): the strands' 16 control points
    # alone take 96 bytes in the asset. In memory the thick levels' cross-sections add about 43
    # bytes a strand (0.58x in all); a file or pack leaves them out and fits them again on reading
    # (measured 0.43x; 0.58x before that).
    import hairlod
    from hairlod import hairmesh

    mesh = hairmesh.read(str(Path(__file__).resolve().parents[2] / "examples" / "data" / "wavy_cap.hairmesh.json"))
    strands = hairlod.generate_strands(mesh, count=20000, vertices=17, seed=1)
    asset = lod.build_lod(strands)
    assert asset.stored_bytes <= 0.5 * lod.strand_bytes(strands)
    assert len(lod.pack(asset)) <= 0.5 * lod.strand_bytes(strands)
    assert asset.memory_bytes > asset.stored_bytes


@pytest.mark.parametrize("view", ["near", "mid", "far"])
def test_coarsest_thick_hairs_cover_like_their_strands(real_hair, asset, view):
    # Every cluster drawn at L0 (a threshold no width exceeds): its 39 hairs, some of hundreds of
    # strands and wider than long, must let as much sky through as the strands do. Total alpha within
    # 10 % (measured -3 % near and mid, -7 % far; the thick hairs once covered +89 %: their tube caps
    # counted as strands, oblique rays crossed 1/sin(theta) too many strands and rho was floored).
    strands_alpha = render.coverage(real_hair, "pt", view, 96, 64, seed=3).sum()
    l0_alpha = render.coverage(real_hair, "lod", view, 96, 64, asset=asset, width_px=1e9, seed=3).sum()
    assert strands_alpha > 0
    assert abs(l0_alpha / strands_alpha - 1.0) < 0.10, (l0_alpha, strands_alpha)


def test_lod_keeps_the_mean_hair_radiance(real_hair, asset):
    # Mid view, 128 px (the sparse mohawk covers about 60 pixels there): the reference at 512 spp
    # against the LoD at 256 spp (the default selection, eps_w = 2 px). The mean linear radiance over
    # the strands' pixels (alpha > 0.5) per channel within 5 % (the issue's target; measured
    # +0.8 / +0.2 / +0.3 % with a 1024-spp reference; it was +12 / +4 / -1 % before the coverage fixes).
    reference = render.render(real_hair, "pt", "mid", 128, 512, seed=11)["image"]
    image = render.render(real_hair, "lod", "mid", 128, 256, asset=asset, seed=12)["image"]
    hair = render.coverage(real_hair, "pt", "mid", 128, 64, seed=3) > 0.5
    assert hair.sum() > 40
    error = image[hair].mean(axis=0) / reference[hair].mean(axis=0) - 1.0
    assert np.all(np.abs(error) < 0.05), error
