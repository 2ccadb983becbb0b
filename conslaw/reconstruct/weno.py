"""WENO slopes (Jiang & Shu 1996) for the Nessyahu–Tadmor scheme.

The WENO reconstruction gives the point values ``w^-_{j+1/2}`` and ``w^+_{j-1/2}`` at the two faces
of cell ``j``. The slope handed to the scheme is their difference,
``w'_j = w^-_{j+1/2} - w^+_{j-1/2}``. For a quadratic reconstruction ``p`` with cell average
``w_j`` this difference is exactly ``dx p'(x_j)``, and the average of ``p`` over the half cell
``[x_j, x_j + dx/2]`` is exactly ``w_j + w'_j/4``: the paper's quarter-point values (eq. 11) are
then the exact half-cell averages of the piecewise quadratic, which is how the paper uses "WENO
r = 3, piecewise quadratic".

``slope_weno3`` is r = 2 (two linear candidate stencils, third-order face values);
``slope_weno5`` is r = 3 (three quadratic candidates, fifth-order face values).
As for the limiters, the bodies are ufunc-only so they run compiled and vectorised. Squares are
written as products (``x ** 2`` compiles to a call of ``pow``, the product is the same number),
and the functions are inlined into the compiled kernel at numba's level (``inline="always"``;
they are too large for LLVM's inliner, and a call per cell stops the kernel's SIMD code).
"""

from __future__ import annotations

from numba import njit

# Jiang & Shu (1996) regularisation of the smoothness indicators.
WENO_EPSILON = 1e-6


@njit(cache=True, error_model="numpy", inline="always")
def _weno3_face(wm1, w0, wp1):
    """Third-order WENO value at the right face of the middle cell (Jiang & Shu 1996, r = 2)."""
    candidate0 = -0.5 * wm1 + 1.5 * w0
    candidate1 = 0.5 * w0 + 0.5 * wp1
    beta0 = (w0 - wm1) * (w0 - wm1)
    beta1 = (wp1 - w0) * (wp1 - w0)
    alpha0 = (1.0 / 3.0) / ((WENO_EPSILON + beta0) * (WENO_EPSILON + beta0))
    alpha1 = (2.0 / 3.0) / ((WENO_EPSILON + beta1) * (WENO_EPSILON + beta1))
    return (alpha0 * candidate0 + alpha1 * candidate1) / (alpha0 + alpha1)


@njit(cache=True, error_model="numpy", inline="always")
def _weno5_face(wm2, wm1, w0, wp1, wp2):
    """Fifth-order WENO value at the right face of the middle cell (Jiang & Shu 1996, r = 3)."""
    candidate0 = (2.0 * wm2 - 7.0 * wm1 + 11.0 * w0) / 6.0
    candidate1 = (-wm1 + 5.0 * w0 + 2.0 * wp1) / 6.0
    candidate2 = (2.0 * w0 + 5.0 * wp1 - wp2) / 6.0
    curvature0 = wm2 - 2.0 * wm1 + w0
    curvature1 = wm1 - 2.0 * w0 + wp1
    curvature2 = w0 - 2.0 * wp1 + wp2
    gradient0 = wm2 - 4.0 * wm1 + 3.0 * w0
    gradient1 = wm1 - wp1
    gradient2 = 3.0 * w0 - 4.0 * wp1 + wp2
    beta0 = (13.0 / 12.0) * (curvature0 * curvature0) + 0.25 * (gradient0 * gradient0)
    beta1 = (13.0 / 12.0) * (curvature1 * curvature1) + 0.25 * (gradient1 * gradient1)
    beta2 = (13.0 / 12.0) * (curvature2 * curvature2) + 0.25 * (gradient2 * gradient2)
    alpha0 = 0.1 / ((WENO_EPSILON + beta0) * (WENO_EPSILON + beta0))
    alpha1 = 0.6 / ((WENO_EPSILON + beta1) * (WENO_EPSILON + beta1))
    alpha2 = 0.3 / ((WENO_EPSILON + beta2) * (WENO_EPSILON + beta2))
    return (alpha0 * candidate0 + alpha1 * candidate1 + alpha2 * candidate2) / (
        alpha0 + alpha1 + alpha2
    )


@njit(cache=True, error_model="numpy", inline="always")
def slope_weno3(wm2, wm1, w0, wp1, wp2):
    """WENO r = 2 slope: ``w^-_{j+1/2} - w^+_{j-1/2}`` (the left face by mirror symmetry)."""
    return _weno3_face(wm1, w0, wp1) - _weno3_face(wp1, w0, wm1)


@njit(cache=True, error_model="numpy", inline="always")
def slope_weno5(wm2, wm1, w0, wp1, wp2):
    """WENO r = 3 slope: ``w^-_{j+1/2} - w^+_{j-1/2}`` (the left face by mirror symmetry)."""
    return _weno5_face(wm2, wm1, w0, wp1, wp2) - _weno5_face(wp2, wp1, w0, wm1, wm2)
