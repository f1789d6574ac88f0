"""How small can the grade error of an imported GPS road get, whatever the smoother? (issue 15, item 3)

The noise test (tests/test_gpx_noise.py, scripts/gps_noise_study.py) lays a shared road's altitude
along a synthetic path, adds altitude noise of std σ [m] as a first-order Gauss–Markov process
(correlation e^(−Δs/100 m)) and 2 m of horizontal jitter per axis (truckmpc.geo.synthetic), imports
the track (truckmpc.roads.gps.importer) and measures the grade RMS error of the imported road against the
true one, in percentage points of grade [pp] (truckmpc.geo.study.grade_rms_error_pct). The issue's
aim is 0.3 pp at σ = 2 m. This script takes the same seeded tracks, the altitude the importer
resamples on its uniform grid before smoothing (ImportedRoad.raw_altitude_m), and smooths it in
several ways, each measured with the same grade_rms_error_pct:

- ``spline default``: the importer's default, the cubic smoothing spline for an assumed σ of 2 m
  (176 m bandwidth), as the noise test and the table of docs/validation/gps.md use it;
- ``spline rule``: the spline for the actual σ (Smoothing.for_noise, 140 m × (σ / 1 m)^(1/3));
- ``spline oracle length`` [ORACLE]: the spline bandwidth, on a 10 m grid, with the least mean error
  over the seeds, chosen knowing the truth;
- ``Wiener exact`` [ORACLE]: the non-causal Wiener filter H(k) = S_sig(k) / (S_sig(k) + S_noise(k))
  on the altitude, S_sig = |X(k)|² / M the exact periodogram of the true altitude on the same grid and
  S_noise the power spectrum of the Gauss–Markov noise sampled at the grid step Δ (an AR(1) sequence,
  σ²(1 − ρ²) / |1 − ρ e^(−iω)|², ρ = e^(−Δ/100 m)); both on the even (mirror) extension of the
  profile, so that the circular filter sees no jump at the ends. For a fixed road this is the best
  linear shift-invariant filter in expectation over the noise, for the altitude and, being diagonal
  in k, equally for the grade: no linear shift-invariant smoother does better on average. Shown
  as measured on the seeded tracks, and as its expectation over the noise,
  Σ_k |D(k)|² [(1 − H)² S_sig + H² S_noise] / M, D the grade (difference) operator, split into the
  road detail the filter removes (bias) and the noise it lets through;
- ``Wiener smooth spectrum`` [ORACLE]: the same with S_sig the true periodogram averaged over
  quarter-octave bands in wavenumber, a smooth prior spectrum as a stationary road model would give;
- ``RTS coloured``: a Rauch–Tung–Striebel smoother whose state is the altitude, the grade (a random
  walk of spectral density q [1/m]) and the Gauss–Markov noise (σ and 100 m given, as a user would
  give their receiver's), measured as altitude + noise + 2 cm white; q by maximum likelihood on the
  track itself (no truth);
- ``L1 trend filter`` [ORACLE, with --l1]: a non-linear smoother, the altitude minimising the
  whitened (AR(1)) squared residual + λ Σ |second difference| (sparse grade changes, as a road of
  straight grades would have), λ chosen knowing the truth; ADMM, slow.

Conditions: altitude noise and jitter (the noise test), noise only (jitter 0, the same altitude
noise: it is drawn before the jitter), jitter only (σ = 0, 2 m jitter) and clean (neither). Last,
per road, the σ [m] at which the expected exact Wiener error equals the aim. One process; about
30 s on the default roads (2 min with --l1).

    python scripts/smoothing_bound.py [--road FILE ...] [--km A-B] [--sigmas 2,5] [--seeds 3] [--aim-pct 0.3] [--l1]

Default roads: the VECTO long-haul 100 km and the US EPA 20 km profiles from ../shared/roads (or
$TRUCKMPC_SHARED_ROADS).
"""

from __future__ import annotations

import argparse
import itertools
import math
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np
from scipy import sparse
from scipy.linalg import cho_solve_banded, cholesky_banded
from scipy.optimize import brentq, minimize_scalar
from study_roads import default_road_paths, road_part

from truckmpc.geo.study import grade_rms_error_pct
from truckmpc.geo.synthetic import noisy_track_gpx
from truckmpc.roads import RoadProfile, load_road
from truckmpc.roads.gps.importer import import_track
from truckmpc.roads.gps.smooth import Smoothing
from truckmpc.roads.gpx import read_gpx
from truckmpc.units import PCT_PER_FRACTION

CORR_M = 100.0
JITTER_M = 2.0
WHITE_M = 0.02
SPLINE_LENGTHS_M = np.arange(80.0, 430.0, 10.0)
CLEAN_SPLINE_LENGTHS_M = np.arange(10.0, 210.0, 10.0)
LOG10_Q_RANGE = (-9.0, -5.0)
L1_LAMBDAS = (1.0, 1.5, 2.0, 3.0, 5.0, 7.0, 10.0, 14.0)

Track = tuple[np.ndarray, np.ndarray]  # grid distance [m], resampled raw altitude [m]


def raw_tracks(road: RoadProfile, sigma_m: float, jitter_m: float, seeds: range) -> list[Track]:
    """The importer's uniform grid and unsmoothed altitude for each seeded track of `road`."""
    tracks = []
    with tempfile.TemporaryDirectory(prefix="truckmpc-bound-") as directory:
        for seed in seeds:
            path = Path(directory) / f"{road.name}-sigma{sigma_m:g}-seed{seed}.gpx"
            document = noisy_track_gpx(road, sigma_m, seed, corr_m=CORR_M, jitter_m=jitter_m)
            path.write_text(document.to_xml(version="1.1"), encoding="utf-8")
            # The grid and the raw altitude do not depend on the smoothing, but the importer's road
            # must pass the grade check, which raw σ = 5 m tracks do not: the default spline.
            imported = import_track(read_gpx(path), Smoothing("spline", 176.0))
            tracks.append((imported.profile.distance_m, imported.raw_altitude_m))
    return tracks


def grade_error_pct(distance_m: np.ndarray, altitude_m: np.ndarray, truth: RoadProfile) -> float:
    """grade_rms_error_pct [pp] of the smoothed altitude on the importer's grid."""
    return grade_rms_error_pct(RoadProfile("smoothed", distance_m, altitude_m - altitude_m[0]), truth)


def truth_on(distance_m: np.ndarray, truth: RoadProfile) -> np.ndarray:
    return np.asarray(np.interp(distance_m, truth.distance_m - truth.distance_m[0], truth.altitude_m))


def spline(distance_m: np.ndarray, altitude_m: np.ndarray, length_m: float) -> np.ndarray:
    """The cubic smoothing spline of bandwidth `length_m` [m] of the altitude on the grid."""
    return applied(Smoothing("spline", length_m))(distance_m, altitude_m)


def applied(smoothing: Smoothing) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    """`smoothing` as a function of (grid distance [m], altitude [m])."""
    return lambda distance_m, altitude_m: smoothing.apply(float(distance_m[1] - distance_m[0]), altitude_m)


def _mirror(values: np.ndarray) -> np.ndarray:
    return np.concatenate([values, values[-2:0:-1]])


def ar1_psd(size: int, step_m: float, sigma_m: float) -> np.ndarray:
    """E|N(k)|² / M [m²] of the Gauss–Markov noise sampled every `step_m`, at the M DFT wavenumbers."""
    rho = math.exp(-step_m / CORR_M)
    omega = 2 * math.pi * np.arange(size) / size
    return np.asarray(sigma_m**2 * (1 - rho**2) / np.abs(1 - rho * np.exp(-1j * omega)) ** 2)


def _band_average(power: np.ndarray, bands_per_octave: int = 4) -> np.ndarray:
    """`power` (a DFT's, symmetric) averaged over log-spaced bands of wavenumber."""
    half = power.size // 2 + 1
    edges = np.unique(np.round(2.0 ** np.arange(0.0, math.log2(half) + 1.0, 1.0 / bands_per_octave)).astype(int))
    edges = np.unique(np.concatenate([[0, 1], edges[edges < half], [half]]))
    smooth = np.empty(half)
    for first, stop in itertools.pairwise(edges):
        smooth[first:stop] = power[first:stop].mean()
    index = np.minimum(np.arange(power.size), power.size - np.arange(power.size))
    return smooth[index]


def wiener(
    distance_m: np.ndarray, altitude_m: np.ndarray, true_m: np.ndarray, sigma_m: float, smooth_spectrum: bool = False
) -> tuple[np.ndarray, tuple[float, float, float]]:
    """The oracle Wiener filter's altitude [m], and its expected grade RMS error, its bias and noise
    parts [pp] (see the module doc)."""
    step_m = float(distance_m[1] - distance_m[0])
    mean_m = float(altitude_m.mean())
    observed = np.fft.fft(_mirror(altitude_m - mean_m))
    size = observed.size
    signal = np.abs(np.fft.fft(_mirror(true_m - true_m.mean()))) ** 2 / size
    if smooth_spectrum:
        signal = _band_average(signal)
    noise = ar1_psd(size, step_m, sigma_m)
    gain = signal / (signal + noise)
    difference = np.abs(1 - np.exp(-2j * math.pi * np.arange(size) / size)) ** 2 / step_m**2
    bias = float(np.sum(difference * (1 - gain) ** 2 * signal)) / size
    passed = float(np.sum(difference * gain**2 * noise)) / size
    expected = tuple(PCT_PER_FRACTION * math.sqrt(v) for v in (bias + passed, bias, passed))
    smoothed = np.real(np.fft.ifft(gain * observed))[: altitude_m.size] + mean_m
    return smoothed, (expected[0], expected[1], expected[2])


def rts_model(step_m: float, q: float, sigma_m: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Transition, process noise covariance and measurement row of the state (altitude [m], grade [-],
    Gauss–Markov noise [m]) over one step; the grade a random walk of spectral density `q` [1/m]."""
    rho = math.exp(-step_m / CORR_M)
    transition = np.array([[1.0, step_m, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, rho]])
    process = np.zeros((3, 3))
    process[:2, :2] = q * np.array([[step_m**3 / 3, step_m**2 / 2], [step_m**2 / 2, step_m]])
    process[2, 2] = sigma_m**2 * (1 - rho**2)
    return transition, process, np.array([1.0, 0.0, 1.0])


def rts(altitude_m: np.ndarray, step_m: float, q: float, sigma_m: float) -> tuple[np.ndarray, float]:
    """The RTS-smoothed altitude [m] and the log-likelihood of the track (innovations after the first two)."""
    transition, process, row = rts_model(step_m, q, sigma_m)
    size = altitude_m.size
    state = np.array([altitude_m[0], 0.0, 0.0])
    cov = np.diag([1e4, 0.1**2, sigma_m**2])
    filtered = np.empty((size, 3))
    filtered_cov = np.empty((size, 3, 3))
    predicted = np.empty((size, 3))
    predicted_cov = np.empty((size, 3, 3))
    loglik = 0.0
    for k in range(size):
        if k > 0:
            state = transition @ state
            cov = transition @ cov @ transition.T + process
        predicted[k], predicted_cov[k] = state, cov
        gain_num = cov @ row
        innovation_var = float(row @ gain_num) + WHITE_M**2
        innovation = float(altitude_m[k] - row @ state)
        if k >= 2:
            loglik -= 0.5 * (math.log(2 * math.pi * innovation_var) + innovation**2 / innovation_var)
        gain = gain_num / innovation_var
        state = state + gain * innovation
        cov = cov - np.outer(gain, gain_num)
        cov = 0.5 * (cov + cov.T)
        filtered[k], filtered_cov[k] = state, cov
    smoothed = filtered.copy()
    for k in range(size - 2, -1, -1):
        back = filtered_cov[k] @ transition.T @ np.linalg.inv(predicted_cov[k + 1])
        smoothed[k] = filtered[k] + back @ (smoothed[k + 1] - predicted[k + 1])
    return smoothed[:, 0], loglik


def rts_coloured(distance_m: np.ndarray, altitude_m: np.ndarray, sigma_m: float) -> np.ndarray:
    """The RTS smoother with q by maximum likelihood on the track (σ and 100 m given)."""
    step_m = float(distance_m[1] - distance_m[0])
    fit = minimize_scalar(
        lambda log_q: -rts(altitude_m, step_m, 10.0**log_q, sigma_m)[1],
        bounds=LOG10_Q_RANGE,
        method="bounded",
        options={"xatol": 0.05},
    )
    return rts(altitude_m, step_m, 10.0 ** float(fit.x), sigma_m)[0]


def l1_trend(distance_m: np.ndarray, altitude_m: np.ndarray, sigma_m: float, lam: float) -> np.ndarray:
    """argmin_h ½‖W(y − h)‖² + λ Σ|h[k+1] − 2h[k] + h[k−1]| (W whitens the AR(1) noise) by ADMM."""
    size = altitude_m.size
    rho = math.exp(-float(distance_m[1] - distance_m[0]) / CORR_M)
    scale = sigma_m * math.sqrt(1 - rho**2)
    whiten = sparse.diags([np.r_[math.sqrt(1 - rho**2), np.ones(size - 1)], -rho * np.ones(size - 1)], [0, -1]) / scale
    second = sparse.diags([1.0, -2.0, 1.0], [0, 1, 2], shape=(size - 2, size)).tocsr()
    penalty = lam / 0.01  # ADMM step: soft threshold of 1 cm of second difference
    system = (whiten.T @ whiten + penalty * (second.T @ second)).todia()
    banded = np.zeros((3, size))
    for offset in range(3):
        banded[2 - offset, offset:] = system.diagonal(offset)
    factor = cholesky_banded(banded)
    rhs = whiten.T @ (whiten @ altitude_m)
    h, z, u = altitude_m.copy(), second @ altitude_m, np.zeros(size - 2)
    for _ in range(1500):
        h = cho_solve_banded((factor, False), rhs + penalty * (second.T @ (z - u)))
        curvature = second @ h
        z = np.sign(curvature + u) * np.maximum(np.abs(curvature + u) - lam / penalty, 0.0)
        u += curvature - z
    return np.asarray(h)


def _errors(
    tracks: list[Track], truth: RoadProfile, smoother: Callable[[np.ndarray, np.ndarray], np.ndarray]
) -> list[float]:
    return [grade_error_pct(d, smoother(d, y), truth) for d, y in tracks]


def _cell(errors: list[float]) -> str:
    return f"{np.mean(errors):.3f} ({max(errors):.3f})"


def _oracle_scan(
    tracks: list[Track], truth: RoadProfile, values: tuple[float, ...] | np.ndarray, smoother: Callable[..., np.ndarray]
) -> tuple[float, list[float]]:
    """The value (of `smoother`'s last argument) with the least mean error, and its errors."""
    best: tuple[float, float, list[float]] | None = None
    for value in values:
        errors = _errors(tracks, truth, lambda d, y, v=value: smoother(d, y, v))
        if best is None or np.mean(errors) < best[0]:
            best = (float(np.mean(errors)), float(value), errors)
    assert best is not None
    return best[1], best[2]


def road_rows(road: RoadProfile, sigmas_m: list[float], seeds: range, l1: bool) -> list[str]:
    rows = []
    default = Smoothing.for_noise("spline", 2.0)

    def row(sigma_m: float, jitter_m: float, method: str, errors: list[float], note: str = "") -> None:
        rows.append(f"| {road.name} | {sigma_m:g} | {jitter_m:g} | {method} | {_cell(errors)} | {note} |")
        print(rows[-1], flush=True)

    for sigma_m, jitter_m in [(0.0, 0.0), (0.0, JITTER_M)]:
        tracks = raw_tracks(road, sigma_m, jitter_m, seeds)
        row(sigma_m, jitter_m, "none", _errors(tracks, road, lambda d, y: y))
        row(sigma_m, jitter_m, f"spline default {default.length_m:g} m", _errors(tracks, road, applied(default)))
        length_m, errors = _oracle_scan(tracks, road, CLEAN_SPLINE_LENGTHS_M, spline)
        row(sigma_m, jitter_m, "spline oracle length [ORACLE]", errors, f"{length_m:g} m")
    for sigma_m in sigmas_m:
        for jitter_m in (JITTER_M, 0.0):
            tracks = raw_tracks(road, sigma_m, jitter_m, seeds)
            rule = Smoothing.for_noise("spline", sigma_m)
            row(sigma_m, jitter_m, f"spline default {default.length_m:g} m", _errors(tracks, road, applied(default)))
            row(sigma_m, jitter_m, f"spline rule {rule.length_m:g} m", _errors(tracks, road, applied(rule)))
            length_m, errors = _oracle_scan(tracks, road, SPLINE_LENGTHS_M, spline)
            row(sigma_m, jitter_m, "spline oracle length [ORACLE]", errors, f"{length_m:g} m")
            exact = [wiener(d, y, truth_on(d, road), sigma_m) for d, y in tracks]
            expected = np.mean([e for _, e in exact], axis=0)
            row(
                sigma_m,
                jitter_m,
                "Wiener exact [ORACLE]",
                [grade_error_pct(d, h, road) for (d, _), (h, _) in zip(tracks, exact, strict=True)],
                f"expected {expected[0]:.3f} (bias {expected[1]:.3f}, noise {expected[2]:.3f})",
            )
            row(
                sigma_m,
                jitter_m,
                "Wiener smooth spectrum [ORACLE]",
                _errors(tracks, road, lambda d, y, s=sigma_m: wiener(d, y, truth_on(d, road), s, True)[0]),
            )
            row(
                sigma_m,
                jitter_m,
                "RTS coloured (ML q)",
                _errors(tracks, road, lambda d, y, s=sigma_m: rts_coloured(d, y, s)),
            )
            if l1 and jitter_m > 0:
                lam, errors = _oracle_scan(tracks, road, L1_LAMBDAS, lambda d, y, v, s=sigma_m: l1_trend(d, y, s, v))
                row(sigma_m, jitter_m, "L1 trend filter [ORACLE]", errors, f"lambda {lam:g}")
    return rows


def sigma_at_aim_m(road: RoadProfile, seeds: range, aim_pct: float) -> float:
    """The σ [m] at which the expected exact Wiener grade error on the first seed's grid is `aim_pct`."""
    ((distance_m, _),) = raw_tracks(road, 0.0, 0.0, seeds[:1])
    true_m = truth_on(distance_m, road)
    return float(brentq(lambda s: wiener(distance_m, true_m, true_m, s)[1][0] - aim_pct, 0.05, 10.0, xtol=1e-3))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--road", type=Path, action="append", help="road CSV with the true altitude; repeatable")
    parser.add_argument("--km", default=None, help="only the part A-B [km] of each road, e.g. 0-25")
    parser.add_argument("--sigmas", default="2,5", help="altitude noise std values [m], comma-separated")
    parser.add_argument("--seeds", type=int, default=3, help="tracks per case (seeds 1..N)")
    parser.add_argument("--aim-pct", type=float, default=0.3, help="the grade error aim [pp]")
    parser.add_argument("--l1", action="store_true", help="also the L1 trend filter (slow)")
    args = parser.parse_args()
    seeds = range(1, args.seeds + 1)
    sigmas_m = [float(x) for x in args.sigmas.split(",")]
    print(f"Gauss-Markov altitude noise, correlation {CORR_M:g} m; jitter per axis [m]; seeds 1..{args.seeds}")
    print("grade RMS error [pp]: mean over the seeds (max)")
    print("| road | sigma [m] | jitter [m] | smoothing | grade RMS error [pp] | note |")
    print("|---|---|---|---|---|---|")
    aims = []
    for path in args.road or default_road_paths():
        road = road_part(load_road(path), args.km)
        road_rows(road, sigmas_m, seeds, args.l1)
        aims.append(f"{road.name}: sigma {sigma_at_aim_m(road, seeds, args.aim_pct):.2f} m")
    print(f"sigma at which the expected exact Wiener error is {args.aim_pct:g} pp: {'; '.join(aims)}")


if __name__ == "__main__":
    main()
