"""Unit conversions the package repeats: SI inside, km/h, km and % at the interfaces.

Multiply by a factor to go from the unit after ``PER`` to the one before it:
``v_kmh = v_mps * KMH_PER_MPS``, ``grade_pct = grade * PCT_PER_FRACTION``.
"""

from __future__ import annotations

import math

KMH_PER_MPS = 3.6
"""km/h per m/s."""

M_PER_KM = 1000.0
"""Metres per kilometre."""

PCT_PER_FRACTION = 100.0
"""Percent per unit fraction: grades (0.01 = 1 %) and relative differences."""

G_PER_KG = 1000.0
"""Grams per kilogram."""

J_PER_KWH = 3.6e6
"""Joules per kilowatt-hour."""

KG_PER_T = 1000.0
"""Kilograms per tonne."""

W_PER_KW = 1000.0
"""Watts per kilowatt."""

RPM_PER_RAD_S = 30.0 / math.pi
"""Engine speed in rpm per angular speed in rad/s."""
