"""Smoothing of an elevation profile sampled on a uniform distance grid.

Methods, each with one length scale `length_m` [m]:

- ``spline`` (the default): a cubic smoothing spline (``scipy.interpolate.make_smoothing_spline``)
  minimising Σ (h_i − f(s_i))² + λ ∫ f''(s)² ds with λ = `length_m`⁴ / Δs, so that `length_m` is
  the bandwidth of its equivalent kernel (Silverman 1984): the altitude passes with gain
  1 / (1 + (k·`length_m`)⁴) at wavenumber k, so features shorter than about 2π·`length_m` are damped.
  It is also the Rauch–Tung–Striebel smoother of a road whose grade wanders as a random walk.
- ``savgol``: Savitzky–Golay (``scipy.signal.savgol_filter``), a local least-squares quadratic over a
  window of `length_m` (rounded to an odd number of points), the ends fitted by the same polynomial.
- ``none``: the resampled altitude as it is.

The length follows the expected noise of the elevations, σ [m]: ``Smoothing.for_noise`` takes
`length_m` = c·(σ / 1 m)^(1/3), c = 140 m for the spline and 1000 m for Savitzky–Golay. The
exponent balances the two errors of a smoother: the road's own curvature flattened (growing as
length²) against the noise let through (falling as length^(−1/2) to length^(−3/2), depending on how
rough the noise is); c is the best length at σ = 1 m in the noise study
(``scripts/gps_noise_study.py --smooth-m``). The spline is the default because it has the lower
grade error wherever there is noise (docs/validation/gps.md has the study's figures).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import make_smoothing_spline
from scipy.signal import savgol_filter

from truckmpc.errors import RoadError

__all__ = ["LENGTH_AT_1M_NOISE_M", "METHODS", "Smoothing"]

METHODS = ("spline", "savgol", "none")
"""Smoothing methods by name; the first is the default."""

LENGTH_AT_1M_NOISE_M = {"spline": 140.0, "savgol": 1000.0}
"""Length scale [m] of each method at an elevation noise of 1 m (see the module doc)."""

_NOISE_EXPONENT = 1.0 / 3.0
_SAVGOL_ORDER = 2


@dataclass(frozen=True)
class Smoothing:
    """A smoothing method and its length scale `length_m` [m] (see the module doc)."""

    method: str
    length_m: float = 0.0

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise RoadError(f"smoothing: expected one of {', '.join(METHODS)}, got {self.method!r}")
        if self.method != "none" and not (math.isfinite(self.length_m) and self.length_m > 0):
            raise RoadError(f"smoothing {self.method}: expected a length > 0 m, got {self.length_m!r}")

    @classmethod
    def for_noise(cls, method: str, noise_m: float) -> Smoothing:
        """`method` with the length scale for elevations of noise std `noise_m` [m] (0: none)."""
        if not (math.isfinite(noise_m) and noise_m >= 0):
            raise RoadError(f"smoothing: elevation noise: expected a number >= 0 m, got {noise_m!r}")
        if method == "none" or noise_m == 0:
            return cls("none")
        if method not in LENGTH_AT_1M_NOISE_M:
            raise RoadError(f"smoothing: expected one of {', '.join(METHODS)}, got {method!r}")
        return cls(method, round(LENGTH_AT_1M_NOISE_M[method] * noise_m**_NOISE_EXPONENT, 1))

    def describe(self, step_m: float) -> str:
        """One line saying what :meth:`apply` does on a grid of `step_m` [m]."""
        if self.method == "savgol":
            points = _savgol_points(self.length_m, step_m)
            return (
                f"savgol, Savitzky-Golay of order {_SAVGOL_ORDER} over {self.length_m:g} m "
                f"({points} points of {step_m:.3f} m)"
            )
        if self.method == "spline":
            return (
                f"spline, cubic smoothing spline of bandwidth {self.length_m:g} m "
                f"(lambda = bandwidth^4 / step = {self.length_m**4 / step_m:.4g} m^3)"
            )
        return "none, the resampled elevation as it is"

    def apply(self, step_m: float, altitude_m: np.ndarray) -> np.ndarray:
        """The smoothed altitude [m] of `altitude_m` sampled every `step_m` [m]. A profile too short
        for the method (under 5 points) is returned as it is."""
        if self.method == "none" or altitude_m.size < 5:
            return altitude_m.copy()
        if self.method == "savgol":
            points = min(_savgol_points(self.length_m, step_m), altitude_m.size - (1 - altitude_m.size % 2))
            return np.asarray(savgol_filter(altitude_m, points, _SAVGOL_ORDER, mode="interp"))
        distance_m = step_m * np.arange(altitude_m.size)
        spline = make_smoothing_spline(distance_m, altitude_m, lam=self.length_m**4 / step_m)
        return np.asarray(spline(distance_m))


def _savgol_points(window_m: float, step_m: float) -> int:
    """Odd number of grid points covering about `window_m`, at least 5."""
    return max(2 * round(window_m / (2 * step_m)) + 1, 5)
