#pragma once
// Longitudinal scattering functions M_p (and the Gaussian lobes shared with azimuthal terms), normalised so that the integral of M cos(theta_i) over
// theta_i in [-pi/2, pi/2] is 1 (d'Eon et al. 2011) or the integral over theta_i is 1 (Gaussians).

namespace hairlod::bcsdf {

// log I_0(x) for x >= 0: the power series below 50, the asymptotic series
// e^x / sqrt(2 pi x) * sum_k ((2k-1)!!)^2 / (k! (8x)^k) above; relative error below 1e-14.
double log_bessel_i0(double x);

// log(e^-x I_0(x)) for x >= 0, without the cancellation of log_bessel_i0(x) - x at large x.
double log_scaled_bessel_i0(double x);

// d'Eon et al. 2011 (Chiang et al. 2016, Sec. 4.1): the rough-cone lobe of variance v,
//   M = exp(-sin_i sin_o / v) I_0(cos_i cos_o / v) / (2 v sinh(1 / v)),
// evaluated in log space so that it is exact (normalised to 1e-12) for every v in [1e-7, 10].
double deon_longitudinal(double sin_theta_i, double cos_theta_i, double sin_theta_o, double cos_theta_o, double v);

// The same lobe with its cone tilted by `shift` (Chiang et al. 2016, Sec. 4): the outgoing angle is
// rotated so that the lobe is centred on theta_i + theta_o = 2 shift; the rotation is applied to
// theta_o, which keeps the normalisation over theta_i exact.
double tilted_deon_longitudinal(double sin_theta_i, double cos_theta_i, double sin_theta_o, double cos_theta_o,
                                double shift, double v);

// Unit-area Gaussian in theta_i of variance `variance` centred on 2 shift - theta_o: Marschner's
// lobe g(theta_h - shift) in the measure d theta_i (Xu et al. 2011, Eq. 7 up to the factor 2 of
// d theta_h = d theta_i / 2).
double gaussian_longitudinal(double theta_i, double theta_o, double shift, double variance);

// Normalised Gaussian of variance `variance` at x.
double gaussian(double x, double variance);

// The same Gaussian wrapped onto the circle: a unit-area density on [-pi, pi) for every variance
// (periods summed up to variance 4, its Fourier series above).
double wrapped_gaussian(double x, double variance);

}  // namespace hairlod::bcsdf
