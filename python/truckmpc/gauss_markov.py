"""First-order Gauss–Markov (AR(1)) noise: the model of a GPS receiver's altitude error and of a
map's grade error in this project's noise studies."""

from __future__ import annotations

import numpy as np

__all__ = ["gauss_markov"]


def gauss_markov(rho: np.ndarray, sigma: float, shocks: np.ndarray) -> np.ndarray:
    """A stationary AR(1) sequence of standard deviation `sigma` (in the caller's unit) from the
    standard normal draws `shocks`, one per value: value 0 is σ·shocks[0], value i is
    rho[i−1]·value(i−1) + σ·√(1 − rho[i−1]²)·shocks[i], rho[i−1] the correlation [-] between values
    i−1 and i (e^(−Δs / correlation length) for points Δs apart)."""
    kicks = sigma * np.sqrt(1.0 - rho**2) * shocks[1:]
    noise = np.empty(shocks.size)
    noise[0] = sigma * shocks[0]
    for i in range(1, noise.size):
        noise[i] = rho[i - 1] * noise[i - 1] + kicks[i - 1]
    return noise
