import numpy as np
import pytest

import hairlod


def make_strands():
    points = np.array([[0, 0, 0], [0, 0, 1], [1, 0, 0], [1, 0, 1], [1, 0, 2]], dtype=np.float32)
    return hairlod.Strands(points, [0, 2, 5], np.full(5, 0.1, np.float32))


def test_contract_dtypes_and_shapes():
    strands = make_strands()
    assert len(strands) == 2
    assert strands.point_count == 5
    assert strands.points.dtype == np.float32 and strands.points.shape == (5, 3)
    assert strands.offsets.dtype == np.int64 and list(strands.offsets) == [0, 2, 5]
    assert strands.radius.dtype == np.float32 and strands.radius.shape == (5,)
    assert list(strands.counts()) == [2, 3]


def test_views_are_zero_copy_and_offsets_read_only():
    strands = make_strands()
    strands.points[4, 2] = 9.0
    strands.radius[:] = 0.25
    assert strands.points[4, 2] == 9.0
    assert np.all(strands.radius == 0.25)
    assert np.shares_memory(strands.points, strands.points)
    with pytest.raises(ValueError):
        strands.offsets[0] = 1


def test_view_keeps_strands_alive():
    points = make_strands().points  # the Strands object itself is gone
    assert points[4, 2] == 2.0


def test_from_counts_and_default_radius():
    points = np.zeros((4, 3), np.float64)
    points[:, 0] = np.arange(4)
    strands = hairlod.Strands.from_counts(points, [2, 2])
    assert list(strands.offsets) == [0, 2, 4]
    assert np.all(strands.radius == 0.0)
    assert strands.points[3, 0] == 3.0


@pytest.mark.parametrize(
    "points, offsets, radius, message",
    [
        (np.zeros((4, 3)), [0, 2, 2, 4], None, "strictly increasing"),
        (np.zeros((4, 3)), [0, 1, 4], None, "curve 0 has 1 point"),
        (np.array([[0, 0, 0], [np.nan, 0, 0]]), [0, 2], None, "point 1 is not finite"),
        (np.array([[0, 0, 0], [np.inf, 0, 0]]), [0, 2], None, "point 1 is not finite"),
        (np.zeros((2, 3)), [0, 2], np.array([0.1, -0.1]), "radius[1] is negative"),
        (np.zeros((2, 2)), [0, 2], None, "shape [N, 3]"),
        (np.zeros((3, 3)), [0, 2], None, "offsets end at 2 but there are 3 points"),
    ],
)
def test_validation_names_the_problem(points, offsets, radius, message):
    with pytest.raises(ValueError, match=message.replace("[", r"\[").replace("]", r"\]")):
        hairlod.Strands(points, offsets, radius)


def test_attributes_by_domain():
    strands = make_strands()
    color = np.arange(15, dtype=np.float32).reshape(5, 3)
    strands.set_attribute("color", color)
    strands.set_attribute("clump", np.array([1.0, 2.0], np.float32), domain="curve")
    assert strands.attribute_names() == ["clump", "color"]
    assert strands.attribute_domain("clump") == "curve"
    np.testing.assert_array_equal(strands.attribute("color"), color)
    with pytest.raises(ValueError, match="needs 5 values"):
        strands.set_attribute("bad", np.ones(2, np.float32))
    with pytest.raises(ValueError, match="domain"):
        strands.set_attribute("bad", np.ones(2, np.float32), domain="face")
    with pytest.raises(KeyError):
        strands.attribute("missing")
    strands.remove_attribute("clump")
    assert strands.attribute_names() == ["color"]


def test_copy_is_independent():
    strands = make_strands()
    duplicate = strands.copy()
    duplicate.points[0] = 5.0
    assert strands.points[0, 0] == 0.0


def test_metrics():
    strands = make_strands()
    lower, upper = strands.bounding_box()
    np.testing.assert_array_equal(lower, [0, 0, 0])
    np.testing.assert_array_equal(upper, [1, 0, 2])
    np.testing.assert_allclose(strands.curve_lengths(), [1.0, 2.0])


def test_resampled_is_even_in_arc_length():
    points = np.array([[0, 0, 0], [0.1, 0, 0], [1, 0, 0]], np.float32)
    strands = hairlod.Strands(points, [0, 3], np.array([1, 1, 3], np.float32))
    resampled = strands.resampled(5)
    assert len(resampled) == 1 and resampled.point_count == 5
    np.testing.assert_allclose(resampled.points[:, 0], np.linspace(0, 1, 5), atol=2e-3)
    with pytest.raises(ValueError, match="points_per_curve"):
        strands.resampled(1)


def test_empty_strands():
    strands = hairlod.Strands(np.zeros((0, 3)), [0])
    assert len(strands) == 0
    assert strands.points.shape == (0, 3)
