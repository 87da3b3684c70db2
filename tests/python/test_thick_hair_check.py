"""bench thick-hairs: each thick level against its member strands (hairlod.thick_hair_check), on
straight bundles where the answer is known: members of equal length end in their hair's last
section, members placed uniformly at random cross as the Poisson model counts. Fixed seeds."""

import json

import numpy as np
import pytest

from test_cli import one_line_error, run_cli
from hairlod import Strands, io, lod, thick_hair_check
from hairlod.hair_params import as_params

POINTS = 10


def _parallel_strands(lengths, seed=3, radius=0.01):
    """Straight strands along z from roots uniform in the unit disc, `lengths` long."""
    rng = np.random.default_rng(seed)
    roots = rng.uniform(-1.0, 1.0, (4 * len(lengths), 2))
    roots = roots[(roots ** 2).sum(axis=1) <= 1.0][:len(lengths)]
    z = np.linspace(0.0, 1.0, POINTS)[None, :] * np.asarray(lengths, np.float64)[:, None]
    points = np.concatenate([np.broadcast_to(roots[:, None, :], (len(lengths), POINTS, 2)), z[..., None]], axis=-1)
    offsets = np.arange(len(lengths) + 1, dtype=np.int64) * POINTS
    return Strands(points.reshape(-1, 3).astype(np.float32), offsets, np.full(len(lengths) * POINTS, radius, np.float32))


def _rest(asset):
    rest = asset.skin(None)["strands"]
    nc = asset.control_points
    return rest.points.reshape(-1, nc, 3).astype(np.float64), rest.radius.reshape(-1, nc)


def test_members_of_equal_length_end_in_the_last_section_and_unequal_ones_pass_it():
    equal = lod.build_lod(_parallel_strands(np.full(600, 10.0)), guides=16)
    points, _ = _rest(equal)
    for level in equal.levels:
        ends = thick_hair_check.member_ends(level, points)
        # Only the stored coordinates' rounding separates the tips from the mean tip's plane.
        assert abs(ends["tips_beyond_p90"]) < 1e-3 and abs(ends["tips_beyond_max"]) < 1e-3, ends
        assert abs(ends["roots_before_p90"]) < 1e-3, ends
    lengths = np.random.default_rng(4).uniform(5.0, 15.0, 600)
    unequal = lod.build_lod(_parallel_strands(lengths), guides=16)
    points, _ = _rest(unequal)
    for level in unequal.levels:
        ends = thick_hair_check.member_ends(level, points)
        # About half the members are longer than their hair's mean (k-means groups strands of like
        # lengths, so a hair's spread is less than the input's +-50 %): they pass its end.
        assert 0.35 < ends["tips_beyond_fraction"] < 0.65 and ends["tips_beyond_p90"] > 0.3, ends
        assert abs(ends["roots_before_p90"]) < 1e-3, ends  # the roots share a plane


def test_lines_cross_uniform_members_as_the_model_counts():
    # One guide: the coarsest level is one hair holding every strand, uniform in the disc its
    # ellipse is fitted to (finer levels split it into k-means cells, which no ellipse fits).
    asset = lod.build_lod(_parallel_strands(np.full(2000, 10.0), radius=0.0005), guides=1)
    points, radius = _rest(asset)
    assert len(asset.levels[0].n_total) == 1
    every_strand = np.arange(asset.strand_count)
    result = thick_hair_check.crossings(asset.levels[0], lambda h: every_strand, points, radius, np.random.default_rng(0),
                                        rays=2000)
    # About one strand met across the hair, half of one from a member outwards: members over the model's
    # count within 10 % (measured 0.99 and 0.94), the share of lines passing none within 0.03 (0.002
    # and 0.015).
    for kind in ("across", "from_member"):
        c = result[kind]
        assert c["lines"] == 6000 and c["model"] > 0.3
        assert 0.9 < c["members"] / c["model"] < 1.1, (kind, c)
        assert abs(c["members_transmittance"] - c["model_transmittance"]) < 0.03, (kind, c)


def test_aggregated_thick_hair_lit_from_behind_sends_what_its_strands_do():
    # The model's own case: one thick hair holding 2000 strands uniform in its sections, lit from
    # behind, seen across its middle. The aggregated BCSDF's transmission lobe (N_TT as wide as the
    # material's TT, widened along the fibre by dual scattering's beta_f^2 per crossing) sends
    # 1.03 / 1.07 / 1.26 of its strands' light (R / G / B, 32 spp, fixed seeds); with N_TT as wide as
    # the logistic alone and the azimuthal sigma_f^2 widening it along the fibre it sent 2.4-2.8x.
    asset = lod.build_lod(_parallel_strands(np.full(2000, 10.0), radius=0.0005), guides=1)
    points, radius = _rest(asset)
    every_strand = np.arange(asset.strand_count)
    result = thick_hair_check.renders_against_members(asset.levels[0], lambda h: every_strand, points, radius,
                                                      as_params(None), np.random.default_rng(0), hairs=1, spp=32)
    behind = np.array(result["ratios"][thick_hair_check.RENDERED_AGGREGATED]["behind"])
    assert np.all((behind > 0.8) & (behind < 1.35)), behind


@pytest.fixture(scope="module")
def hanging(tmp_path_factory):
    from test_lod import hanging_hair

    path = tmp_path_factory.mktemp("thick") / "hanging.hair"
    io.write(path, hanging_hair(curves=600, points=10))
    return path


def test_bench_reports_every_level_and_renders_the_single_fibre_both_ways_and_the_aggregated_bcsdf(hanging):
    strands = io.read(hanging)
    result = thick_hair_check.bench_thick_hairs(strands, guides=8, hairs=2, spp=2, lines_hairs=5)
    asset_levels = len(lod.build_lod(strands, guides=8).levels)
    assert [level["level"] for level in result["levels"]] == list(range(asset_levels))
    for level in result["levels"]:
        assert level["renders"]["hairs"] == 2
        for kind in ("attenuate", "scatter", thick_hair_check.RENDERED_AGGREGATED):
            ratios = np.array([level["renders"]["ratios"][kind][side] for side in thick_hair_check.LIGHT_SIDES])
            assert ratios.shape == (3, 3) and np.all(np.isfinite(ratios)) and np.all(ratios > 0.0)
        assert set(level["crossings"]) == {"across", "from_member"}
    table = thick_hair_check.format_tables(result)
    assert len([line for line in table.splitlines() if line.startswith("| ")]) == 2 + asset_levels  # header, rule, levels
    with pytest.raises(ValueError, match="hairs, spp and lines hairs must be >= 1"):
        thick_hair_check.bench_thick_hairs(strands, hairs=0)


def test_cli_bench_thick_hairs(hanging):
    result = run_cli("bench", "thick-hairs", hanging, "--guides", 8, "--hairs", 1, "--spp", 2, "--json")
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["component"] == "thick-hairs" and report["spp"] == 2 and report["levels"]
    assert "needs an input hair file" in one_line_error(run_cli("bench", "thick-hairs"))
    assert "--hairs" in one_line_error(run_cli("bench", "thick-hairs", hanging, "--hairs", 0))


def test_thick_hairs_hold_the_strands_that_cross_their_sections():
    # A fanning bundle whose strands grow longer across it (length 10 + 5 x, leaning 0.3 x): the k-th
    # points of its strands lie on planes tilted from the strands, and a section fitted to them there
    # misses most strands where they really cross it. The sections are fitted where the strands cross
    # the plane normal to their mean tangent: every level holds at least 85 % of its members there
    # (the build asks 95 % of the exact sections; the stored ones are rounded). Fitted to the k-th
    # points, as Sec. 5.1 step 3 has it, the same bundle's levels held 56-66 %.
    rng = np.random.default_rng(5)
    roots = rng.uniform(-1.0, 1.0, (3000, 2))
    roots = roots[(roots ** 2).sum(axis=1) <= 1.0][:1200]
    lengths = 10.0 + 5.0 * roots[:, 0]
    direction = np.stack([0.3 * roots[:, 0], np.zeros(len(roots)), np.ones(len(roots))], axis=1)
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    t = np.linspace(0.0, 1.0, POINTS)[None, :, None] * lengths[:, None, None]
    points = np.concatenate([roots, np.zeros((len(roots), 1))], axis=1)[:, None, :] + t * direction[:, None, :]
    offsets = np.arange(len(roots) + 1, dtype=np.int64) * POINTS
    hair = Strands(points.reshape(-1, 3).astype(np.float32), offsets, np.full(len(roots) * POINTS, 0.01, np.float32))
    asset = lod.build_lod(hair, guides=16)
    rest, _ = _rest(asset)
    assert len(asset.levels) >= 2
    for level in asset.levels:
        through = thick_hair_check.strands_through_sections(
            level.centres, level.major_axis * level.radii[..., :1], level.minor_axis * level.radii[..., 1:], level.membership, rest)
        assert through >= 0.85, f"{through:.3f} of the members pass through their sections (coverage {level.coverage:.3f})"
