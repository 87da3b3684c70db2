"""hairlod.hairmesh and `python3 -m hairlod generate`: the Python side of strand generation."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO

import hairlod
from hairlod import hairmesh

EXAMPLES = REPO / "examples" / "data"
EXAMPLE_FILES = sorted(EXAMPLES.glob("*.hairmesh.json"))


def grid_mesh(nx=3, ny=2, layers=3, lean=0.3):
    """nx x ny quads on z = 0, extruded upwards with a lean along x."""
    grid = np.array([[x, y, 0.0] for y in range(ny + 1) for x in range(nx + 1)], dtype=np.float32)
    stack = np.array([grid + [lean * layer * layer, 0.0, layer] for layer in range(layers)], dtype=np.float32)
    faces = [[y * (nx + 1) + x, y * (nx + 1) + x + 1, (y + 1) * (nx + 1) + x + 1, (y + 1) * (nx + 1) + x]
             for y in range(ny) for x in range(nx)]
    return hairlod.HairMesh(stack, np.full(len(faces), 4, np.int32), np.array(faces, np.int32).ravel())


def run_cli(*args):
    env = dict(os.environ, PYTHONPATH=str(REPO / "addon"))
    return subprocess.run([sys.executable, "-m", "hairlod", *map(str, args)], capture_output=True, text=True,
                          env=env, cwd=REPO)


ALL_STYLING = [
    {"op": "curl", "radius": 0.1, "frequency": 1.0, "randomness": 0.5},
    {"op": "wave", "amplitude": 0.1, "frequency": 0.5},
    {"op": "twist", "rate": 0.1},
    {"op": "clump", "amount": 0.5, "profile": 2.0},
    {"op": "frizz", "amplitude": 0.02, "frequency": 4.0},
    {"op": "trim", "amount": 0.2},
]


def test_generate_strands_attributes_and_counts():
    strands = hairlod.generate_strands(grid_mesh(), count=600, vertices=17, styling=ALL_STYLING, seed=2)
    assert len(strands) == 600
    assert np.all(strands.counts() == 17)
    assert sorted(strands.attribute_names()) == ["bundle", "tangent", "uvw"]
    assert strands.attribute("tangent").shape == (strands.point_count, 3)
    assert strands.attribute("uvw").shape == (strands.point_count, 3)
    assert strands.attribute_domain("bundle") == "curve"
    # Equal faces get equal shares (largest remainders): 100 strands in each of the 6 bundles.
    assert np.all(np.bincount(strands.attribute("bundle").astype(int)) == 100)
    assert np.all(np.isfinite(strands.points))
    strands.validate()


def test_roots_lie_on_the_root_layer():
    strands = hairlod.generate_strands(grid_mesh(), count=1000, vertices=9, styling=ALL_STYLING, seed=5)
    roots = strands.points[strands.offsets[:-1]]
    lower, upper = strands.bounding_box()
    assert np.max(np.abs(roots[:, 2])) < 1e-5 * np.linalg.norm(upper - lower)


def test_deterministic_per_seed():
    a = hairlod.generate_strands(grid_mesh(), count=300, styling=ALL_STYLING, seed=9)
    b = hairlod.generate_strands(grid_mesh(), count=300, styling=ALL_STYLING, seed=9)
    c = hairlod.generate_strands(grid_mesh(), count=300, styling=ALL_STYLING, seed=10)
    assert np.array_equal(a.points, b.points)
    assert np.array_equal(a.attribute("tangent"), b.attribute("tangent"))
    assert not np.array_equal(a.points, c.points)


@pytest.mark.parametrize("lod", [1.0, 0.6, 0.3, 0.01])
def test_every_strand_has_power_of_two_plus_one_vertices(lod):
    strands = hairlod.generate_strands(grid_mesh(), count=200, vertices=33, lod=(1.0, lod))
    expected = 2 ** max(0, int(np.ceil(5 + np.log2(lod)))) + 1
    assert np.all(strands.counts() == expected)


def test_strand_lod_thickens_fewer_strands():
    full = hairlod.generate_strands(grid_mesh(), count=1200, vertices=5, radius=0.01)
    half = hairlod.generate_strands(grid_mesh(), count=1200, vertices=5, radius=0.01, lod=(0.5, 1.0))
    assert 600 <= len(half) <= 606  # Bhokare 2024 Eq. 8: ceil(L (N + delta)) per bundle, 6 bundles
    assert half.radius[0] == pytest.approx(2 * full.radius[0])


def test_subdivision_refines_the_bundles():
    strands = hairlod.generate_strands(grid_mesh(), count=500, vertices=9, subdivision=2)
    assert int(strands.attribute("bundle").max()) == 6 * 16 - 1
    assert grid_mesh().subdivided(2).face_count == 96


def test_styling_dicts_round_trip_and_errors():
    operations = hairmesh.styling_from_dicts(ALL_STYLING)
    assert [type(op).__name__ for op in operations] == ["Curl", "Wave", "Twist", "Clump", "Frizz", "Trim"]
    assert repr(operations[0]) == "Curl(radius=0.1, frequency=1, randomness=0.5)"
    again = hairmesh.styling_to_dicts(operations)
    assert again[0] == {"op": "curl", "radius": 0.1, "frequency": 1.0, "randomness": 0.5}
    with pytest.raises(ValueError, match=r"styling\[0\]: unknown operation 'perm'"):
        hairmesh.styling_from_dicts([{"op": "perm"}])
    with pytest.raises(ValueError, match=r"unknown parameter 'size'"):
        hairmesh.styling_from_dicts([{"op": "curl", "size": 1}])
    with pytest.raises(ValueError, match=r"styling operation 0 \(clump\): amount must be in \[0, 1\]"):
        hairlod.generate_strands(grid_mesh(), count=10, styling=[{"op": "clump", "amount": 2}])


def test_file_round_trip(tmp_path):
    mesh = grid_mesh()
    path = tmp_path / "grid.hairmesh.json"
    hairmesh.write(path, mesh, ALL_STYLING[:2], strand_radius=0.02)
    loaded = hairmesh.read(path)
    assert np.array_equal(loaded.mesh.layers, mesh.layers)
    assert np.array_equal(loaded.mesh.face_vertices, mesh.face_vertices)
    assert hairmesh.styling_to_dicts(loaded.styling) == hairmesh.styling_to_dicts(hairmesh.styling_from_dicts(ALL_STYLING[:2]))
    assert loaded.strand_radius == 0.02
    # The file's styling and radius are the defaults of generate_strands.
    strands = hairlod.generate_strands(loaded, count=50, vertices=5)
    assert np.allclose(strands.radius, 0.02)
    assert [p.name for p in tmp_path.iterdir()] == ["grid.hairmesh.json"]


@pytest.mark.parametrize("change, message", [
    (lambda d: d.update(format="other"), "'format' must be"),
    (lambda d: d.update(version=2), "unsupported version 2"),
    (lambda d: d.update(extra=1), "unknown key 'extra'"),
    (lambda d: d.pop("faces"), "missing 'faces'"),
    (lambda d: d["faces"].append([0, 1, 99]), "outside"),
    (lambda d: d["faces"].append([0, 1, 1]), "degenerate"),
    (lambda d: d["layers"].pop(), "at least one extrusion layer"),
    (lambda d: d["layers"][1].pop(), "nested|list of numbers|levels"),
    (lambda d: d["layers"][1][0].__setitem__(0, float("nan")), "NaN is not a JSON number"),
    (lambda d: d.update(uv=[[[0, 0]]]), "one \\[u, v\\] per face corner"),
    (lambda d: d.update(strand_radius=-1), "strand_radius"),
    (lambda d: d.update(styling=[{"op": "curl", "radius": "big"}]), "radius must be a finite number"),
])
def test_bad_files_name_the_problem(tmp_path, change, message):
    data = hairmesh.hair_mesh_to_dict(grid_mesh(2, 1, 2))
    change(data)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=message) as error:
        hairmesh.read(path)
    assert str(path) in str(error.value)


def test_hard_cases():
    # Zero-area face among others: valid output without strands in it.
    layers = grid_mesh(2, 1, 3).layers
    layers[:, 2] = layers[:, 1]
    layers[:, 5] = layers[:, 4]
    mesh = hairlod.HairMesh(layers, [4, 4], [0, 1, 4, 3, 1, 2, 5, 4])
    strands = hairlod.generate_strands(mesh, count=100, styling=ALL_STYLING)
    assert len(strands) == 100 and np.all(strands.attribute("bundle") == 0)
    # Coincident layers, a single face with a single extrusion layer, huge coordinates.
    flat = grid_mesh().layers
    flat[1:] = flat[0]
    assert np.all(np.isfinite(hairlod.generate_strands(hairlod.HairMesh(flat, [4] * 6, grid_mesh().face_vertices),
                                                       count=50, styling=ALL_STYLING).attribute("tangent")))
    single = hairlod.generate_strands(grid_mesh(1, 1, 2), count=20, vertices=3)
    assert len(single) == 20
    huge = grid_mesh()
    scaled = hairlod.HairMesh(huge.layers * 1e6, [4] * 6, huge.face_vertices)
    strands = hairlod.generate_strands(scaled, count=100, styling=ALL_STYLING)
    assert np.all(np.isfinite(strands.points))
    # Clear errors: zero total area, bad vertex count, bad LoD.
    zero = np.zeros((2, 4, 3), np.float32)
    with pytest.raises(ValueError, match="zero"):
        hairlod.generate_strands(hairlod.HairMesh(zero, [4], [0, 1, 2, 3]), count=10)
    with pytest.raises(ValueError, match="2\\^e \\+ 1"):
        hairlod.generate_strands(grid_mesh(), count=10, vertices=10)
    with pytest.raises(ValueError, match="LoD must be in"):
        hairlod.generate_strands(grid_mesh(), count=10, lod=0.0)


def test_detail_level_eq7():
    assert hairmesh.detail_level(0.1, 1000.0, 1000.0, 0.5) == pytest.approx(0.1 * 1000 / (1000 * np.tan(0.5)))


@pytest.mark.parametrize("path", EXAMPLE_FILES, ids=[p.name for p in EXAMPLE_FILES])
def test_cli_generate_json(path):
    assert len(EXAMPLE_FILES) == 2
    result = run_cli("generate", path, "--count", 3000, "--vertices", 9, "--json")
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["strands"] == 3000 and report["points"] == 27000 and report["points_per_strand"] == 9
    assert report["generate_seconds"] > 0 and report["output"] is None
    assert report["styling"], "the example files carry styling"


@pytest.mark.parametrize("args, message", [
    (["missing.json"], "missing.json"),
    (["{example}", "--vertices", "10"], "vertices must be 2^e + 1"),
    (["{example}", "--count", "0"], "--count: must be between 1 and"),
    (["{example}", "--subdivision", "5"], "--subdivision: must be between 0 and 3"),
    (["{example}", "--lod", "2"], "--lod: must be <= 1"),
])
def test_cli_generate_bad_input(args, message):
    example = EXAMPLE_FILES[0]
    result = run_cli("generate", *[a.format(example=example) for a in args])
    assert result.returncode == 2
    assert message in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    assert "Traceback" not in result.stderr


def test_cli_generate_writes_hair_file(tmp_path):
    out = tmp_path / "cap.hair"
    result = run_cli("generate", EXAMPLES / "wavy_cap.hairmesh.json", "--count", 500, "--out", out, "--json")
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["write_seconds"] >= 0
    info = json.loads(run_cli("info", out, "--json").stdout)
    assert info["strands"] == 500 and info["points"] == 500 * 17


def test_bench_generate_reports_consistent_sizes():
    from hairlod import bench

    result = bench.bench_generate(strands=1000, vertices=9, repeats=1)
    assert result["points"] == 1000 * 9
    # points, radius, tangent and uvw per point; offsets and bundle per strand.
    assert result["output_bytes"] == 9000 * (12 + 4 + 12 + 12) + 1001 * 8 + 1000 * 4
    assert set(result["operations"]) == {"curl", "wave", "twist", "clump", "frizz", "trim"}
    assert result["storage"]["strand_bytes"] == 9000 * 16 + 1001 * 8
    assert 0 < result["storage"]["hair_mesh_json_bytes"] < result["storage"]["strand_bytes"]
    assert all(result[key] > 0 for key in ("generate_s", "copy_s", "generate_no_styling_s"))


def test_generate_into_reused_output_matches_a_fresh_one():
    from hairlod import bench, hairmesh

    generator = hairmesh.strand_generator(bench.bench_hair_mesh(), 500, 3)
    styling = hairmesh.styling_from_dicts(bench.BENCH_STYLING)
    out = generator.generate(vertices=5)
    again = generator.generate(vertices=9, styling=styling, out=out)
    fresh = generator.generate(vertices=9, styling=styling)
    assert again is out
    assert np.array_equal(again.points, fresh.points) and np.array_equal(again.offsets, fresh.offsets)
    assert np.array_equal(again.attribute("tangent"), fresh.attribute("tangent"))


def test_generator_reuses_root_samples_only_when_they_are_the_same():
    # Moving vertices keeps the bundles' strand counts, so the sample sets of the earlier generator
    # are the ones needed: the strands must be exactly those of a generator built from scratch.
    mesh = grid_mesh()
    moved = grid_mesh(lean=0.5)
    earlier = hairmesh.strand_generator(mesh, 300, 4)
    fresh = hairmesh.strand_generator(moved, 300, 4).generate(vertices=9)
    reused = hairmesh.strand_generator(moved, 300, 4, reuse=earlier).generate(vertices=9)
    assert np.array_equal(reused.points, fresh.points)
    # Another seed or count needs other sets: the earlier ones must not be taken.
    for count, seed in ((300, 5), (5000, 4)):
        expected = hairmesh.strand_generator(moved, count, seed).generate(vertices=5)
        actual = hairmesh.strand_generator(moved, count, seed, reuse=earlier).generate(vertices=5)
        assert np.array_equal(actual.points, expected.points), (count, seed)


def _two_quads():
    """Two unit quads side by side in z = 0 (6 vertices), face normals +z, per-loop UVs = (x, y)."""
    positions = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]], np.float32)
    loop_vertices = np.array([0, 1, 4, 3, 1, 2, 5, 4], np.int32)
    return dict(positions=positions, loop_vertices=loop_vertices, loop_starts=[0, 4], loop_totals=[4, 4],
                face_normals=[[0, 0, 1], [0, 0, 1]], face_areas=[1.0, 1.0],
                loop_uv=positions[loop_vertices, :2].copy())


def test_extrude_faces_grows_the_selected_faces_along_their_normals():
    mesh = hairmesh.extrude_faces(**_two_quads(), selected=[False, True], layers=3, length=0.6, taper=0.0)
    assert (mesh.layer_count, mesh.face_count, mesh.vertex_count) == (4, 1, 4)
    layers = mesh.layers
    np.testing.assert_allclose(layers[0][:, :2], [[1, 0], [2, 0], [1, 1], [2, 1]])  # the selected quad's corners
    np.testing.assert_allclose(layers[:, :, 2], np.repeat([[0.0], [0.2], [0.4], [0.6]], 4, axis=1), atol=1e-6)
    np.testing.assert_allclose(mesh.uv, layers[0][mesh.face_vertices.ravel(), :2], atol=1e-6)


def test_extrude_faces_tapers_each_layer_towards_its_centre_and_takes_all_faces_when_none_is_selected():
    mesh = hairmesh.extrude_faces(**_two_quads(), selected=[False, False], layers=2, length=1.0, taper=0.5)
    assert (mesh.face_count, mesh.vertex_count) == (2, 6)
    layers = mesh.layers
    centre = layers[0].mean(axis=0)
    for k in range(3):
        np.testing.assert_allclose(layers[k][:, :2] - centre[:2], (layers[0][:, :2] - centre[:2]) * 0.5 ** k, atol=1e-6)


@pytest.mark.parametrize("change, match", [({"layers": 0}, "layers"), ({"taper": 1.0}, "taper"),
                                           ({"loop_starts": [], "loop_totals": [], "face_normals": np.zeros((0, 3)),
                                             "face_areas": [], "selected": []}, "no faces"),
                                           ({"face_areas": [1.0]}, "one entry per face")])
def test_extrude_faces_names_bad_input(change, match):
    arguments = dict(_two_quads(), selected=[True, True], layers=2, length=1.0, taper=0.0)
    arguments.update(change)
    with pytest.raises(ValueError, match=match):
        hairmesh.extrude_faces(**arguments)
