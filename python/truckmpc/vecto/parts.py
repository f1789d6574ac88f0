"""What the core's map-based truck (``_core.MapTruck``) is built from besides the engine as read
(:class:`~truckmpc.vecto.components.EngineData`): the driveline and the body, each value named with
its unit. The core reads them by attribute and checks them."""

from __future__ import annotations

from dataclasses import dataclass

from truckmpc.vecto.components import LossPoints

__all__ = ["Body", "Driveline"]


@dataclass(frozen=True)
class Driveline:
    """A gearbox and axle with their losses, and the driven tyres' radius."""

    gear_ratios: tuple[float, ...]
    """Ratio of each gear, first gear first [-]."""
    axle_ratio: float
    gear_efficiency: float
    """Efficiency of the gears where no loss map is given [-]."""
    axle_efficiency: float
    """Efficiency of the axle where no loss map is given [-]."""
    loss_torque_nm: float
    """Drag at the gearbox input where no loss map is given [Nm]."""
    wheel_radius_m: float
    """The driven tyres' dynamic radius [m]."""
    gear_loss_maps: tuple[LossPoints, ...] | None = None
    """One loss map per gear, replacing gear_efficiency and loss_torque_nm."""
    axle_loss_map: LossPoints | None = None
    """The axle's loss map, replacing axle_efficiency."""
    retarder_loss_map: tuple[tuple[float, float], ...] | None = None
    """The retarder's (retarder speed [rpm], torque loss [Nm]) rows; None: no retarder losses."""
    retarder_ratio: float = 1.0
    """The retarder's speed per speed of the shaft it turns with [-]."""
    retarder_position: str = "output"
    """The gearbox shaft the retarder turns with: "input" or "output"."""


@dataclass(frozen=True)
class Body:
    """The truck's body and load."""

    mass_kg: float
    """Total mass: curb, trailer and payload [kg]."""
    wheels_inertia_kgm2: float
    """Every wheel's inertia together [kg m²]."""
    cda_m2: float
    """Drag area Cd·A without cross wind [m²]."""
    air_density_kgpm3: float
    rolling_resistance: float
    """The combination's rolling resistance coefficient [-]."""
    aux_power_w: float
    """The auxiliaries' power [W]."""
    cda_curve: tuple[tuple[float, float], ...] | None = None
    """(speed [m/s], Cd·A [m²]) rows replacing cda_m2 by a drag area over speed (cross wind)."""
