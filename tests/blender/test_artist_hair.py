"""examples/make_artist_hair.py: guides on a head, children by Geometry Nodes, read through the bridge."""

import importlib.util
import os

import bpy
import numpy as np
import pytest
from mathutils.bvhtree import BVHTree

from hairlod import io

EXAMPLE = os.path.join(os.path.dirname(__file__), os.pardir, os.pardir, "examples", "make_artist_hair.py")
CHILDREN, GUIDES, SEED = 2000, 40, 3


def load_example():
    spec = importlib.util.spec_from_file_location("make_artist_hair", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def example():
    return load_example()


@pytest.fixture(scope="module")
def artist(example):
    """Plain data of one generated scene (later tests may replace the scene)."""
    head, hair, children = example.generate(CHILDREN, GUIDES, SEED)
    mesh = head.data
    vertices = [vertex.co.copy() for vertex in mesh.vertices]
    polygons = [tuple(polygon.vertices) for polygon in mesh.polygons]
    scalp = np.empty(len(polygons), bool)
    mesh.attributes[example.SCALP_ATTRIBUTE].data.foreach_get("value", scalp)
    evaluated = hair.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    evaluated_points = np.empty((len(evaluated.points), 3), np.float32)
    evaluated.attributes["position"].data.foreach_get("vector", evaluated_points.ravel())
    guides = np.empty((len(hair.data.points), 3), np.float32)
    hair.data.attributes["position"].data.foreach_get("vector", guides.ravel())
    return {
        "children": children, "guides": guides.reshape(len(hair.data.curves), -1, 3),
        "evaluated_curve_count": len(evaluated.curves), "evaluated_points": evaluated_points,
        "head": BVHTree.FromPolygons(vertices, polygons),
        "scalp": BVHTree.FromPolygons(vertices, [p for p, on in zip(polygons, scalp) if on]),
        "scalp_polygons": [[vertices[i] for i in p] for p, on in zip(polygons, scalp) if on],
    }


def shapes(points, count):
    """Root-relative shapes [count, P, 3] of curves of equal point counts."""
    points = points.reshape(count, -1, 3).astype(np.float64)
    return points - points[:, :1]


def test_the_bridge_reads_the_requested_children_as_blender_evaluated_them(artist):
    children = artist["children"]
    assert len(children) == CHILDREN == artist["evaluated_curve_count"]
    assert artist["guides"].shape[0] == GUIDES
    np.testing.assert_array_equal(children.offsets, np.arange(CHILDREN + 1) * artist["guides"].shape[1])
    np.testing.assert_array_equal(children.points, artist["evaluated_points"])
    assert children.radius.min() > 0 and children.radius.max() == pytest.approx(3e-5)


def test_roots_lie_on_the_scalp_spread_like_its_area(artist):
    roots = artist["children"].points[artist["children"].offsets[:-1]]
    distances = np.array([artist["scalp"].find_nearest(root)[3] for root in roots])
    assert distances.max() < 1e-6
    # Per azimuth sector around the vertical, roots in proportion to the scalp's area there.
    centres = np.array([np.mean(polygon, axis=0) for polygon in artist["scalp_polygons"]])
    areas = np.array([_polygon_area(polygon) for polygon in artist["scalp_polygons"]])
    sectors = 8
    expected = np.bincount(_sector(centres, sectors), areas, sectors) / areas.sum() * CHILDREN
    found = np.bincount(_sector(roots, sectors), minlength=sectors)
    np.testing.assert_allclose(found, expected, rtol=0.25)


def test_no_point_is_inside_the_head(artist):
    for points in (artist["children"].points, artist["guides"].reshape(-1, 3)):
        signed = []
        for point in points:
            location, normal, _, _ = artist["head"].find_nearest(point)
            signed.append((point - np.array(location)) @ np.array(normal))
        assert min(signed) > -1e-6


def test_children_interpolate_the_guides_without_copying_them(artist):
    children, guides = shapes(artist["children"].points, CHILDREN), artist["guides"]
    guides = guides - guides[:, :1]
    # Largest point distance from each child's shape to the nearest guide's.
    deviation = np.abs(children[:, None] - guides[None]).max(axis=(2, 3)).min(axis=1)
    assert np.quantile(deviation, 0.01) > 5e-4
    assert np.median(deviation) < 0.03
    assert len(np.unique(children.round(7).reshape(CHILDREN, -1), axis=0)) == CHILDREN


def test_the_same_seed_writes_the_same_bytes(example, tmp_path):
    files = []
    for name, seed in (("first", SEED), ("again", SEED), ("other", SEED + 1)):
        files.append(tmp_path / f"{name}.hair")
        io.write(files[-1], example.generate(CHILDREN, GUIDES, seed)[2])
    first, again, other = (path.read_bytes() for path in files)
    assert first == again
    assert first != other


def _polygon_area(corners):
    corners = np.array(corners)
    return 0.5 * np.linalg.norm(np.cross(corners[1:-1] - corners[0], corners[2:] - corners[0]).sum(axis=0))


def _sector(points, sectors):
    angles = np.arctan2(points[:, 1], points[:, 0])
    return np.minimum(((angles + np.pi) / (2 * np.pi) * sectors).astype(int), sectors - 1)
