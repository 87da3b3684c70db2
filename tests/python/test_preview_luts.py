"""hairlod.preview_luts.forward_share: a_f at a light's inclination to the strand, as the preview's shaders
read it from the dual-scattering table (tests/ui/test_bcsdf_shader.py holds the GLSL to it)."""

import numpy as np

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

