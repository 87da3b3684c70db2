"""Bake sources and table sets: --lod (n range from an LoD folder), --from-blend (a material's
Principled Hair BSDF read by headless Blender), --tables xu (Xu et al. 2011's C_k, H_k)."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import hairlod
from hairlod import bcsdf, bcsdf_bake, hair_params, lod
from hairlod.bench import synthetic_hair

ENV = {**os.environ, "PYTHONPATH": "addon"}

# NumPy 2 renamed trapz; 1.24 (Debian 12) has only the old name.
trapezoid = getattr(np, "trapezoid", None) or np.trapz


def _bake(*arguments):
    return subprocess.run([sys.executable, "-m", "hairlod", "bake", *arguments], capture_output=True, text=True,
                          env=ENV)


def _read_exr(path, channels):
    oiio = pytest.importorskip("OpenImageIO")
    image = oiio.ImageInput.open(str(path))
    names = list(image.spec().channelnames)
    pixels = image.read_image("float")
    image.close()
    return pixels[..., [names.index(c) for c in channels]]


def test_lod_folder_sets_the_hair_count_range(tmp_path):
    strands = synthetic_hair(400, 12, seed=3)
    strands.radius[:] = 0.02  # thick enough that rays cross several hairs (and rho reaches its cap 1)
    asset = lod.build_lod(strands, guides=8, levels=3, control_points=6, seed=1)
    lod.save(asset, tmp_path / "asset")
    crossed, densest = bcsdf.lod_hair_count_range(lod.load(tmp_path / "asset"))
    # Brute force: hairs_crossed (Sec. 4) at the longest chord 2 r_A of every control point.
    expected = 1.0
    for level in asset.levels:
        for h in range(len(level.n_total)):
            for c in range(level.radii.shape[1]):
                r_a, r_b = (float(v) for v in level.radii[h, c])
                if r_a > 0 and r_b > 0:
                    n = bcsdf.hairs_crossed(min(float(level.density[h, c]), 1.0), 2 * r_a, float(level.n_total[h]), r_a, r_b)
                    expected = max(expected, min(n, float(level.n_total[h])))
    assert crossed == pytest.approx(expected, rel=2e-3)  # the folder stores radii quantised
    assert densest == max(int(level.n_total.max()) for level in asset.levels)
    assert 1.0 < crossed <= densest
    run = _bake("--lod", str(tmp_path / "asset"), "--out", str(tmp_path / "lut"), "--json")
    assert run.returncode == 0, run.stderr
    result = json.loads(run.stdout)
    assert result["max_hair_count"] == pytest.approx(crossed) and result["densest_cluster_strands"] == densest
    manifest = json.loads((tmp_path / "lut" / "manifest.json").read_text())
    aggregated = next(t for t in manifest["tables"] if t["name"] == "aggregated_attenuation")
    assert aggregated["axes"][1]["range"] == pytest.approx([1.0, crossed])
    bad = _bake("--lod", str(tmp_path / "nothing"), "--out", str(tmp_path / "lut2"))
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "nothing" in bad.stderr
    assert not (tmp_path / "lut2").exists()


def test_xu_tables_match_their_integrals(tmp_path):
    manifest = bcsdf_bake.bake({}, tmp_path / "lut", tables=["xu"])
    tables = {t["name"]: t for t in manifest["tables"]}
    assert sorted(tables) == ["xu_cosine", "xu_h_trt", "xu_h_tt"]
    cosine = tables["xu_cosine"]
    assert [a["name"] for a in cosine["axes"]] == ["phi", "lambda"] and cosine["axes"][1]["scale"] == "log"
    assert "Eq. 14" in cosine["equation"] and "Eq. 19" in tables["xu_h_tt"]["equation"]  # Xu 2011
    values = _read_exr(tmp_path / "lut" / cosine["file"], cosine["channels"])
    # C_k(lambda, phi) = integral over one period of g^c(x; 0, lambda) |cos((phi - x) / 2)|^k (Xu 2011 Eq. 14),
    # by a 20001-node trapezoid rule, at nodes and between nodes (log-bilinear lookup).
    x = np.linspace(-np.pi, np.pi, 20001)
    rng = np.random.default_rng(5)
    points = np.column_stack([rng.uniform(0, np.pi, 30), np.exp(rng.uniform(np.log(0.05), np.log(10.0), 30))])
    looked_up = bcsdf_bake.lut_lookup(values, cosine["axes"], points)
    for (phi, lam), row in zip(points, looked_up):
        g = np.exp(2.0 * (np.cos(x) - 1.0) / lam ** 2)
        c = np.abs(np.cos(0.5 * (phi - x)))
        expected = np.array([trapezoid(g * c ** k, x) for k in range(7)])
        np.testing.assert_allclose(row, expected, rtol=2e-2, atol=1e-4 * expected[0])
    h_tt = tables["xu_h_tt"]
    assert [a["name"] for a in h_tt["axes"]] == ["theta_d", "eta"] and h_tt["axes"][1]["range"] == [1.0, 10.0]
    values = _read_exr(tmp_path / "lut" / h_tt["file"], h_tt["channels"])
    # Xu 2011 Eq. 19 at the node theta_d = 0, eta = 10 ** (40/127): integral over h of (1 - F)^2 h^k, F the
    # unpolarised Fresnel reflectance at incidence cos = sqrt(1 - h^2).
    eta = 10.0 ** (40 / 127)
    h = np.linspace(-1.0, 1.0, 200001)
    cos_i = np.sqrt(1.0 - h ** 2)
    cos_t = np.sqrt(1.0 - (1.0 - cos_i ** 2) / eta ** 2)
    r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    f = 0.5 * (r_s ** 2 + r_p ** 2)
    expected = [trapezoid((1 - f) ** 2 * h ** k, h) for k in (0, 2, 4)]
    np.testing.assert_allclose(values[40, 0], expected, rtol=1e-4)
    assert bcsdf_bake.bake({}, tmp_path / "both", tables=["aggregated", "xu"])["tables"][3]["name"] == "xu_cosine"
    run = _bake("--tables", "aggregated,nope", "--out", str(tmp_path / "o"))
    assert run.returncode == 2 and "nope" in run.stderr and not (tmp_path / "o").exists()



MAKE_BLEND = """
import bpy, sys, math
hair = bpy.data.materials.new("Hair")
hair.use_nodes = True
nodes = hair.node_tree.nodes
node = nodes.new("ShaderNodeBsdfHairPrincipled")
node.parametrization = "MELANIN"
node.inputs["Melanin"].default_value = 0.6
node.inputs["Melanin Redness"].default_value = 0.3
node.inputs["Tint"].default_value = (0.9, 0.8, 0.7, 1.0)
node.inputs["Roughness"].default_value = 0.25
node.inputs["Radial Roughness"].default_value = 0.4
node.inputs["Coat"].default_value = 0.1
node.inputs["IOR"].default_value = 1.6
node.inputs["Offset"].default_value = math.radians(3.0)
hair.node_tree.links.new(node.outputs[0], nodes["Material Output"].inputs["Surface"])
plain = bpy.data.materials.new("Plain")
plain.use_nodes = True
hair.use_fake_user = plain.use_fake_user = True
bpy.ops.wm.save_as_mainfile(filepath=sys.argv[-1])
"""


@pytest.fixture(scope="module")
def hair_blend(tmp_path_factory, blender):
    path = tmp_path_factory.mktemp("blend") / "hair.blend"
    run = subprocess.run([blender, "-b", "--factory-startup", "--python-expr", MAKE_BLEND, "--", str(path)],
                         capture_output=True, text=True)
    assert path.is_file(), run.stdout + run.stderr
    return path


def test_bake_from_blend_reads_the_principled_hair_node(hair_blend, tmp_path):
    run = _bake("--from-blend", str(hair_blend), "--material", "Hair", "--out", str(tmp_path / "lut"), "--json")
    assert run.returncode == 0, run.stderr
    result = json.loads(run.stdout)
    node = result["principled_hair"]
    assert node["parametrization"] == "MELANIN"
    assert node["melanin"] == pytest.approx(0.6) and node["melanin_redness"] == pytest.approx(0.3)
    assert node["tint"] == pytest.approx([0.9, 0.8, 0.7]) and node["offset"] == pytest.approx(np.radians(3.0))
    expected = hair_params.params_to_dict(hair_params.from_principled_hair(
        parametrization="MELANIN", melanin=0.6, melanin_redness=0.3, tint=(0.9, 0.8, 0.7), roughness=0.25,
        radial_roughness=0.4, coat=0.1, ior=1.6, offset=np.radians(3.0)))
    manifest = json.loads((tmp_path / "lut" / "manifest.json").read_text())
    for name, value in expected.items():
        assert manifest["params"][name] == pytest.approx(value, rel=1e-6), name
        assert result["hair_params"][name] == pytest.approx(value, rel=1e-6), name


@pytest.mark.parametrize("arguments, message", [
    (["--material", "Missing"], "no material named 'Missing'"),
    (["--material", "Plain"], "material 'Plain' has no Principled Hair BSDF node"),
])
def test_bake_from_blend_errors(hair_blend, tmp_path, arguments, message):
    run = _bake("--from-blend", str(hair_blend), *arguments, "--out", str(tmp_path / "lut"))
    assert run.returncode == 2 and run.stdout == ""
    assert run.stderr.count("\n") == 1 and message in run.stderr and "Traceback" not in run.stderr
    assert not (tmp_path / "lut").exists()


def test_bake_from_missing_blend(tmp_path):
    run = _bake("--from-blend", str(tmp_path / "none.blend"), "--material", "Hair", "--out", str(tmp_path / "lut"))
    assert run.returncode == 2 and run.stderr.count("\n") == 1 and "none.blend: no such .blend file" in run.stderr
    run = _bake("--from-blend", str(tmp_path / "none.blend"), "--out", str(tmp_path / "lut"))
    assert run.returncode == 2 and "--material" in run.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == []
