"""hairlod.preview_luts.forward_share: a_f at a light's inclination to the strand, as the preview's shaders
read it from the dual-scattering table (tests/ui/test_bcsdf_shader.py holds the GLSL to it);
scattering_albedo, what the strands scatter of the light they do not pass forwards; and
material_fibre_rows, the material's fibre as the shaders read it."""

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


@pytest.mark.parametrize("params", [DARK, {"sigma_a": (0.06, 0.1, 0.2), "beta_m": 0.25, "beta_n": 0.5}])
def test_material_fibre_rows_hold_the_materials_energy_at_every_inclination(params):
    """The material's fibre for the shader (material_fibre_rows): its lobes' means over phi (each row's last
    texel) add up, times 2 pi, to the fibre's directional albedo at theta_o, the fibre table's A_R + A_TT +
    A_D (the R / TT / D fibre holds the material's energies; 1e-3); each row is non-negative, its last texel
    the mean of the others, and TRRT+'s rows uniform in phi. The rows against C++'s far field: C++
    Chiang.FarFieldTableRebuildsTheFarField; the GLSL against C++: tests/ui/test_bcsdf_shader.py."""
    theta_samples, phi_samples = 17, 33
    rows, shapes = preview_luts.material_fibre_rows(params, theta_samples=theta_samples, phi_samples=phi_samples)
    assert rows.shape == (4 * theta_samples, phi_samples + 1, 4) and rows.dtype == np.float32
    assert len(shapes) == 4 and shapes[3][0] == 0.0 and shapes[3][1] == shapes[2][1]
    values = rows[:, :phi_samples, :3].astype(np.float64)
    assert np.isfinite(values).all() and (values >= 0.0).all()
    weight = np.full(phi_samples, 1.0 / (phi_samples - 1))
    weight[[0, -1]] *= 0.5
    np.testing.assert_allclose(rows[:, -1, :3], np.einsum("rkc,k->rc", values, weight), rtol=1e-5)
    # TRRT+ is uniform in phi.
    np.testing.assert_allclose(values[3 * theta_samples:], np.broadcast_to(rows[3 * theta_samples:, -1:, :3], values[3 * theta_samples:].shape), rtol=1e-5)
    albedo = 2.0 * np.pi * rows[:, -1, :3].astype(np.float64).reshape(4, theta_samples, 3).sum(axis=0)
    tables = preview_luts.shader_tables(params, theta_samples=theta_samples)
    fibre = tables.fiber[:, :, :3].astype(np.float64).sum(axis=0)
    np.testing.assert_allclose(albedo[:-1], fibre[:-1], atol=1e-3)  # theta_o = pi / 2 leaves no azimuth
