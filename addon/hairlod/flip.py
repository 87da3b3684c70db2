"""LDR-FLIP (Andersson, Nilsson, Akenine-Moeller, Oskarsson, Astroem, Fairchild: "FLIP: A Difference
Evaluator for Alternating Images", HPG 2020), implemented from the paper in numpy.

Pipeline (paper Sec. 3-4): sRGB -> linear RGB -> YyCxCz (opponent space); contrast sensitivity
filters (Gaussian sums, Sec. 4.1, FLIP Table/Eq. 2-3) per channel at `pixels_per_degree`; Hunt-adjusted
L*a*b*, HyAB colour distance, compressed towards 1 (FLIP Eq. 4-6); feature (edge and point) detection on
the achromatic channel with Gaussian first and second derivatives (Sec. 4.2, FLIP Eq. 7-9);
E = E_c^(1 - E_f) per pixel (FLIP Eq. 10). Images are [H, W, 3] sRGB in [0, 1]; the mean error is in [0, 1].
"""

import numpy as np

__all__ = ["flip", "flip_map", "pixels_per_degree"]

# Sec. 4.1: the contrast sensitivity functions as sums of Gaussians in the frequency domain,
# (a1, b1, a2, b2) per channel (A: achromatic, RG, BY), spatial extents derived below.
_CSF = {"A": (1.0, 0.0047, 0.0, 1e-5), "RG": (1.0, 0.0053, 0.0, 1e-5), "BY": (34.1, 0.04, 13.5, 0.025)}
_GQC = 0.7      # colour-difference compression exponent (q_c)
_GPC = 0.4      # p_c: knee of the error map
_GPT = 0.95     # p_t
_QF = 0.5       # feature exponent (q_f)
_FEATURE_W = 0.082  # edge/point detector width in degrees (w)


def pixels_per_degree(distance_m=0.7, width_m=0.7, width_px=3840):
    """Pixels per degree of visual angle for a monitor of `width_m` at `distance_m` (paper default ~67)."""
    return distance_m * (width_px / width_m) * np.pi / 180.0


def _srgb_to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def _linear_to_xyz(rgb):
    m = np.array([[0.4124564, 0.3575761, 0.1804375], [0.2126729, 0.7151522, 0.0721750],
                  [0.0193339, 0.1191920, 0.9503041]])
    return rgb @ m.T


def _xyz_to_linear(xyz):
    m = np.linalg.inv(np.array([[0.4124564, 0.3575761, 0.1804375], [0.2126729, 0.7151522, 0.0721750],
                                [0.0193339, 0.1191920, 0.9503041]]))
    return xyz @ m.T


_WHITE = _linear_to_xyz(np.ones(3))


def _xyz_to_ycxcz(xyz):
    x, y, z = (xyz / _WHITE).transpose(2, 0, 1)
    return np.stack([116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)], axis=-1)


def _ycxcz_to_xyz(ycc):
    y = (ycc[..., 0] + 16.0) / 116.0
    x = y + ycc[..., 1] / 500.0
    z = y - ycc[..., 2] / 200.0
    return np.stack([x, y, z], axis=-1) * _WHITE


def _xyz_to_lab(xyz):
    t = xyz / _WHITE
    delta = 6.0 / 29.0
    f = np.where(t > delta ** 3, np.cbrt(t), t / (3 * delta ** 2) + 4.0 / 29.0)
    return np.stack([116.0 * f[..., 1] - 16.0, 500.0 * (f[..., 0] - f[..., 1]), 200.0 * (f[..., 1] - f[..., 2])], -1)


def _convolve(image, kernel):
    """Separable-free 2D convolution with edge clamping (kernels are small)."""
    r = kernel.shape[0] // 2
    padded = np.pad(image, ((r, r), (r, r)), mode="edge")
    out = np.zeros_like(image)
    for dy in range(kernel.shape[0]):
        for dx in range(kernel.shape[1]):
            out += kernel[dy, dx] * padded[dy:dy + image.shape[0], dx:dx + image.shape[1]]
    return out


def _csf_kernel(channel, ppd):
    """Spatial filter of one channel: the inverse Fourier transform of a1 e^(-pi^2 b1 f^2)... a sum of
    Gaussians of variance b_i / (2 pi^2) deg^2, normalised to unit sum (FLIP Eq. 3)."""
    a1, b1, a2, b2 = _CSF[channel]
    radius = int(np.ceil(3.0 * np.sqrt(max(b1, b2) / (2.0 * np.pi ** 2)) * ppd))
    x = np.arange(-radius, radius + 1) / ppd
    d2 = x[None, :] ** 2 + x[:, None] ** 2
    g = a1 * np.sqrt(np.pi / b1) * np.exp(-np.pi ** 2 * d2 / b1) + a2 * np.sqrt(np.pi / b2) * np.exp(-np.pi ** 2 * d2 / b2)
    return g / g.sum()


def _hunt(lab):
    """Hunt effect: chroma scaled by 0.01 L (Sec. 4.1)."""
    return np.stack([lab[..., 0], 0.01 * lab[..., 0] * lab[..., 1], 0.01 * lab[..., 0] * lab[..., 2]], -1)


def _hyab(a, b):
    d = a - b
    return np.abs(d[..., 0]) + np.sqrt(d[..., 1] ** 2 + d[..., 2] ** 2)


def _filtered_lab(srgb, ppd):
    ycc = _xyz_to_ycxcz(_linear_to_xyz(_srgb_to_linear(srgb)))
    filtered = np.stack([_convolve(ycc[..., i], _csf_kernel(c, ppd)) for i, c in enumerate(("A", "RG", "BY"))], -1)
    rgb = np.clip(_xyz_to_linear(_ycxcz_to_xyz(filtered)), 0.0, 1.0)
    return _hunt(_xyz_to_lab(_linear_to_xyz(rgb)))


def _max_distance():
    """cmax: the HyAB distance between Hunt-adjusted green and blue, the largest in sRGB (Sec. 4.1)."""
    green = _hunt(_xyz_to_lab(_linear_to_xyz(np.array([[[0.0, 1.0, 0.0]]]))))
    blue = _hunt(_xyz_to_lab(_linear_to_xyz(np.array([[[0.0, 0.0, 1.0]]]))))
    return float(_hyab(green, blue)[0, 0]) ** _GQC


def _compress(e_c, cmax):
    """FLIP Eq. 5-6: errors below p_c cmax map linearly to [0, p_t], above compressed into (p_t, 1]."""
    pc, pt = _GPC * cmax, _GPT
    return np.where(e_c < pc, e_c * pt / pc, pt + (e_c - pc) / (cmax - pc) * (1.0 - pt))


def _feature_kernels(ppd):
    sigma = 0.5 * _FEATURE_W * ppd
    radius = int(np.ceil(3.0 * sigma))
    x = np.arange(-radius, radius + 1, dtype=np.float64)
    xx, yy = np.meshgrid(x, x)
    g = np.exp(-(xx ** 2 + yy ** 2) / (2 * sigma ** 2))
    edge_x = -xx * g
    edge_x /= np.sum(np.abs(edge_x)) / 2.0  # positive and negative weights each sum to 1
    point_x = (xx ** 2 / sigma ** 2 - 1.0) * g
    positive, negative = point_x[point_x > 0].sum(), -point_x[point_x < 0].sum()
    point_x = np.where(point_x > 0, point_x / positive, point_x / negative)
    return edge_x, edge_x.T, point_x, point_x.T


def _features(achromatic, kernels):
    edge_x, edge_y, point_x, point_y = kernels
    edge = np.hypot(_convolve(achromatic, edge_x), _convolve(achromatic, edge_y))
    point = np.hypot(_convolve(achromatic, point_x), _convolve(achromatic, point_y))
    return edge, point


def flip_map(test, reference, ppd=None):
    """Per-pixel LDR-FLIP error in [0, 1] between two sRGB images [H, W, 3] in [0, 1]."""
    test, reference = (np.clip(np.asarray(v, np.float64), 0.0, 1.0) for v in (test, reference))
    if test.shape != reference.shape or test.ndim != 3 or test.shape[2] != 3:
        raise ValueError(f"flip: images must both be [H, W, 3], got {test.shape} and {reference.shape}")
    ppd = pixels_per_degree() if ppd is None else ppd
    # Colour pipeline (Sec. 4.1).
    cmax = _max_distance()
    e_c = _compress(_hyab(_filtered_lab(test, ppd), _filtered_lab(reference, ppd)) ** _GQC, cmax)
    # Feature pipeline (Sec. 4.2) on the normalised achromatic channel (L* / 100 of Y).
    def achromatic(srgb):
        return (_xyz_to_ycxcz(_linear_to_xyz(_srgb_to_linear(srgb)))[..., 0] + 16.0) / 116.0

    kernels = _feature_kernels(ppd)
    edge_t, point_t = _features(achromatic(test), kernels)
    edge_r, point_r = _features(achromatic(reference), kernels)
    e_f = (np.maximum(np.abs(edge_r - edge_t), np.abs(point_r - point_t)) / np.sqrt(2.0)) ** _QF
    return np.power(e_c, 1.0 - e_f)


def flip(test, reference, ppd=None):
    """Mean LDR-FLIP error (0 = identical)."""
    return float(np.mean(flip_map(test, reference, ppd)))
