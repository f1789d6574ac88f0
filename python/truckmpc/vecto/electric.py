"""A battery-electric truck as VECTO declares it: its electric machines, the reduction between them
and the wheels, its batteries, and the vehicle (masses, air drag, axles, auxiliaries), read from a
declaration XML (:mod:`truckmpc.vecto.electric_xml`). Values are the file's, in its units; what
VECTO makes of them (machines counted, voltage levels, resistances by pulse length) is the model's.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from truckmpc.vecto.components import LossPoints, VehicleData

__all__ = ["BatteryData", "ElectricMachineData", "ElectricTruckJob", "ReductionData", "VoltageLevel"]


@dataclass(frozen=True)
class VoltageLevel:
    """One machine measured at one voltage: its torque limits over speed and its electric power
    map. Speeds are the machine's output shaft's [rpm]; a positive torque drives the truck."""

    voltage_v: float
    continuous_torque_nm: float
    """The torque the machine holds indefinitely, measured at :attr:`continuous_speed_rpm`."""
    continuous_speed_rpm: float
    overload_torque_nm: float
    """The torque it holds for :attr:`overload_duration_s`, measured at :attr:`overload_speed_rpm`."""
    overload_speed_rpm: float
    overload_duration_s: float
    torque_limits: tuple[tuple[float, float, float], ...]
    """(speed [rpm], most driving torque [Nm], most braking torque [Nm], ≤ 0) rows, speeds rising."""
    power_map: tuple[tuple[float, float, float], ...]
    """(speed [rpm], torque [Nm], electric power [W]) points: the power the machine system draws
    from the battery (negative: what it returns while braking)."""


@dataclass(frozen=True)
class ElectricMachineData:
    """The electric machines at one position of the powertrain: ``count`` alike, each described by
    the file's data."""

    position: str
    """Where they act: ``E4`` at the wheels' axle through a reduction (the only one read today)."""
    count: int
    machine_type: str
    """``ASM`` (asynchronous), ``PSM`` (permanent-magnet synchronous), ``ESM`` or ``RM``."""
    rated_power_w: float
    """Each machine's rated power (R85) [W]."""
    inertia_kgm2: float
    """Each machine's rotor inertia [kg m²]."""
    dc_dc_converter_included: bool
    """Whether the power map includes a DC/DC converter's losses."""
    voltage_levels: tuple[VoltageLevel, ...]
    """Ordered by voltage, lowest first."""
    drag_curve: tuple[tuple[float, float], ...]
    """(speed [rpm], drag torque [Nm], ≤ 0) rows: the torque a machine takes turning without current."""


@dataclass(frozen=True)
class ReductionData:
    """The gear between the machines and the wheels (VECTO's ADC at position E4)."""

    ratio: float
    loss_map: LossPoints


@dataclass(frozen=True)
class BatteryData:
    """One battery string (VECTO's REESS of a battery system)."""

    string_id: int
    battery_type: str
    rated_capacity_ah: float
    ocv: tuple[tuple[float, float], ...]
    """(state of charge [%], open-circuit voltage [V]) rows, state of charge rising."""
    resistance: tuple[tuple[float, float, float, float], ...]
    """(state of charge [%], R_2, R_10, R_20) rows: internal resistance for pulses of 2, 10 and 20 s,
    in the file's unit (mΩ)."""
    current_limits: tuple[tuple[float, float, float], ...]
    """(state of charge [%], most charging current [A], most discharging current [A]) rows."""
    soc_min_pct: float
    soc_max_pct: float
    """The usable window of the state of charge [%]."""

    @property
    def usable_capacity_ah(self) -> float:
        """The charge [Ah] between the usable window's ends."""
        return self.rated_capacity_ah * (self.soc_max_pct - self.soc_min_pct) / 100.0


@dataclass(frozen=True)
class ElectricTruckJob:
    """A battery-electric truck read from a VECTO declaration XML."""

    path: Path
    architecture: str
    """VECTO's ArchitectureID (``E4``, …)."""
    vehicle: VehicleData
    machine: ElectricMachineData
    reduction: ReductionData
    batteries: tuple[BatteryData, ...]
    auxiliaries: tuple[tuple[str, str], ...]
    """(auxiliary, technology) pairs as the file names them."""

    @property
    def files(self) -> tuple[Path, ...]:
        """The files the truck was read from: the declaration alone."""
        return (self.path,)
