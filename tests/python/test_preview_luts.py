"""hairlod.preview_luts.forward_share: a_f at a light's inclination to the strand, as the preview's shaders
read it from the dual-scattering table (tests/ui/test_bcsdf_shader.py holds the GLSL to it); and
scattering_albedo, what the strands scatter of the light they do not pass forwards."""

import numpy as np
import pytest

from hairlod import bcsdf, preview_luts

DARK = {"sigma_a": (1.2, 1.8, 3.0), "beta_m": 0.3, "beta_n": 0.3}


def test_forward_share_reads_the_tables_nodes_and_the_fibres_a_f_between_them():
    tables = preview_luts.shader_tables(DARK)
    nodes = np.linspace(-0.5 * np.pi, 0.5 * np.pi, tables.dual.shape[1])
    np.testing.assert_allclose(preview_luts.forward_share(tables, np.sin(nodes)),
                               np.clip(tables.dual[0, :, :3], 1e-4, 1.0), atol=1e-12)
    # Half-way between nodes: linear, and within the table's interpolation error of the R / TT / D fibre's
    # own a_f (the fibre the table is baked from), away from the grazing ends where a_f bends fastest.
    middles = 0.5 * (nodes[:-1] + nodes[1:])
    shares = preview_luts.forward_share(tables, np.sin(middles))
    np.testing.assert_allclose(shares, 0.5 * (tables.dual[0, :-1, :3] + tables.dual[0, 1:, :3]), rtol=1e-6)
    exact = bcsdf.dual_scattering(DARK, middles, model="fiber_rtd")["a_f"]
    inner = np.abs(middles) < 1.2
    assert np.abs(shares - exact)[inner].max() < 3e-3
    # Lights along the strand and past it: clamped, finite, in (0, 1].
    ends = preview_luts.forward_share(tables, np.array([-1.0, 1.0, -2.0, 2.0]))
    assert np.isfinite(ends).all() and (ends >= 1e-4).all() and (ends <= 1.0).all()



@pytest.mark.parametrize("sigma_a", [(0.0, 0.0, 0.0), (0.2, 0.4, 0.8), (1.2, 1.8, 3.0)])
def test_scattering_albedo_is_the_backward_share_of_what_strands_do_not_pass_forwards(sigma_a):
    tables = preview_luts.shader_tables({"sigma_a": sigma_a})
    rho = preview_luts.scattering_albedo(tables)
    # Brute force over the inclinations (a fine midpoint rule on the fibre's own a_f and a_b, directions
    # uniform over the sphere: density cos(theta)): the tables' trapezoids agree within 1 %.
    theta = (np.arange(2000) + 0.5) / 2000 * np.pi - 0.5 * np.pi
    shares = bcsdf.dual_scattering({"sigma_a": sigma_a}, theta, model="fiber_rtd")
    weight = np.cos(theta)[:, None]
    exact = (weight * shares["a_b"]).sum(0) / (weight * (1.0 - shares["a_f"])).sum(0)
    np.testing.assert_allclose(rho, exact, rtol=0.01)
    assert ((rho >= 0.0) & (rho <= 1.0)).all()
    if not any(sigma_a):
        # A fibre that absorbs nothing sends on all it does not pass forwards: a_f + a_b = 1.
        np.testing.assert_allclose(rho, 1.0, atol=1e-6)
    else:
        # Absorbing hair keeps less, the more it absorbs a channel (red absorbed least).
        assert rho[0] > rho[1] > rho[2] and rho.max() < 0.9
