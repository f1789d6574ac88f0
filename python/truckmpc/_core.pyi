"""Types of the native module `truckmpc._core` (the pyo3 binding of truckmpc-core).

Checked against the compiled module by `python -m mypy.stubtest truckmpc._core` in `.ci/run`.
"""

from collections.abc import Mapping, Sequence
from typing import Any, Literal, NotRequired, Protocol, TypeAlias, TypedDict, final

import numpy as np
import numpy.typing as npt

__all__ = [
    "G_MPS2",
    "MapTruck",
    "ParamError",
    "Road",
    "Settings",
    "Vehicle",
    "controllers",
    "declaration",
    "parameter_value",
    "run",
    "run_python",
]

class ParamError(ValueError):
    """An invalid parameter: the key, what was expected, the value given, the other keys involved."""

    key: str
    expected: str
    got: str | None
    related: list[str]

def declaration(name: Literal["parameters", "key_changes", "summary", "trace"]) -> list[dict[str, Any]]:
    """The records of one of the core's declarations, in its order (raises ParamError for another name).

    - "parameters": every declared parameter, section by section (name, section, kind, unit, doc,
      default, choices, expected), typed by `truckmpc.config.keys.ParamSpec`;
    - "key_changes": every key renamed, replaced or added, oldest first (key, kind, new, why,
      replays_with, version), typed by `truckmpc.config.keys.KeyChange`;
    - "summary": every figure of a controller's summary, in `summary.json`'s order, and "trace":
      every column of a run's trace, in the CSV's order (name, unit, label, doc, kind, runs, source,
      merge, merge_of, sweep, decimals), typed by `truckmpc.schema.OutputSpec`.
    """

def parameter_value(key: str, value: Any) -> Any:
    """The value of `key` as the core reads `value`: type and range checked (raises ParamError)."""

class _Derived(TypedDict):
    horizon_stages: int
    """N, the stages of the look-ahead's horizon: round(horizon_m / S), at least 1."""
    replan_stages: int
    """Stages decided from one horizon solve: round(replan_m / S), at least 1."""
    v_ref_range_kmh: list[float]
    """The set speeds [km/h] whose band the truck can drive, [lowest, highest]."""
    kinetic_fuel_g_per_half_v2: float
    """Grams of fuel per unit of ½v² [m²/s²] in the gear the PI settles in at v_ref: the end-speed
    correction's price of kinetic energy."""
    k_lim: int
    """The resolved keys follow, with the values the run uses: k_lim [stages] (null: round(200 m / S))."""
    q_speed_below: float
    """The weight on speed below v_min, per stage."""
    q_brake: float
    """The weight on braking, per stage."""
    beta_g_per_s: NotRequired[float | None]
    """β [g/s] of a truck that burns fuel: None with the speed_penalty cost; derived from v_ref when
    not given."""
    beta_j_per_s: NotRequired[float | None]
    """β [J/s] of a battery-electric truck, in place of beta_g_per_s."""

@final
class Settings:
    """A run's settings and truck, checked against each other: every parameter of a run.

    Args:
        values: mapping of declared keys to user values (YAML-like: numbers, numeric text, bools,
            None, names, lists); keys not given take their declared defaults.
        truck: a truck from component data, replacing the thesis's model of the vehicle keys.

    Raises:
        ParamError: a key is unknown, or a value is of the wrong type, out of its range, or
            inconsistent with another or with the truck (the error's `related` names the others).
    """

    def __new__(cls, values: Mapping[str, Any], truck: MapTruck | None = None) -> Settings: ...
    def with_values(self, changes: Mapping[str, Any]) -> Settings:
        """These settings with `changes` made, the same truck."""
    def values(self) -> dict[str, Any]: ...
    def get(self, key: str) -> Any: ...
    @property
    def vehicle(self) -> Vehicle: ...
    def derived(self) -> _Derived:
        """Figures derived from the settings and the truck, the resolved keys among them."""
    def steady_gear(self, v_mps: float) -> int:
        """The gear the PI gear logic settles in at constant speed `v_mps` [m/s]."""

class _Stationary(TypedDict):
    pedal: float
    brake: float
    feasible: bool
    eigenvalue_per_m: float
    """∂(dv/ds)/∂v [1/m] (tables B.1/B.2)."""
    engine_speed_rpm: float
    engine_torque_nm: float
    fuel_rate_g_per_h: float

@final
class Vehicle:
    """A validated truck model, as `Settings.vehicle` gives it."""

    @property
    def forward_gears(self) -> int: ...
    def engine_speed_rpm(self, v_mps: float, gear: int) -> float: ...
    def engine_torque_nm(self, v_mps: float, pedal: float, gear: int) -> float: ...
    def stationary(self, v_mps: float, slope: float, gear: int) -> _Stationary:
        """The levels holding `v_mps` (> 0) on grade `slope` [-] (Δh/ΔL, 0.01 = 1 %) in `gear`, and the
        engine there."""

G_MPS2: float
"""Gravitational acceleration [m/s²] of the map-based truck (VECTO 3's)."""

_Rows = Sequence[tuple[float, float, float]]

class _EngineData(Protocol):
    """What a MapTruck reads of its engine (a VECTO `EngineData`): idle speed [rpm], inertia
    [kg m²], full-load rows (speed [rpm], full-load and drag torque [Nm]) and fuel map rows
    (speed [rpm], torque [Nm], fuel [g/h])."""

    @property
    def idle_speed_rpm(self) -> float: ...
    @property
    def inertia_kgm2(self) -> float: ...
    @property
    def full_load(self) -> _Rows: ...
    @property
    def fuel_map(self) -> _Rows: ...

class _DrivelineData(Protocol):
    """Gearbox and axle ratios, their losses (affine, or loss maps replacing them), a retarder's loss
    map (retarder speed [rpm], torque loss [Nm]) with its ratio and gearbox shaft ("input" or
    "output"), and the tyres' radius."""

    @property
    def gear_ratios(self) -> Sequence[float]: ...
    @property
    def axle_ratio(self) -> float: ...
    @property
    def gear_efficiency(self) -> float: ...
    @property
    def axle_efficiency(self) -> float: ...
    @property
    def loss_torque_nm(self) -> float: ...
    @property
    def wheel_radius_m(self) -> float: ...
    @property
    def gear_loss_maps(self) -> Sequence[_Rows] | None: ...
    @property
    def axle_loss_map(self) -> _Rows | None: ...
    @property
    def retarder_loss_map(self) -> Sequence[tuple[float, float]] | None: ...
    @property
    def retarder_ratio(self) -> float: ...
    @property
    def retarder_position(self) -> str: ...

class _BodyData(Protocol):
    """Mass [kg], wheels' inertia [kg m²], Cd·A [m²] (or a curve over speed [m/s]), air density
    [kg/m³], rolling resistance [-] and auxiliary power [W]."""

    @property
    def mass_kg(self) -> float: ...
    @property
    def wheels_inertia_kgm2(self) -> float: ...
    @property
    def cda_m2(self) -> float: ...
    @property
    def air_density_kgpm3(self) -> float: ...
    @property
    def rolling_resistance(self) -> float: ...
    @property
    def aux_power_w(self) -> float: ...
    @property
    def cda_curve(self) -> Sequence[tuple[float, float]] | None: ...

class _DrivingState(TypedDict):
    cda_m2: float
    """Drag area at the speed [m²]."""
    air_w: float
    rolling_w: float
    slope_w: float
    vehicle_inertia_w: float
    wheels_inertia_w: float
    wheel_w: float
    """Their sum: the power at the wheels [W]."""
    neutral_drag_w: float
    """Power the axle and an output retarder take from the wheels in neutral [W]."""
    engine_speed_rpm: NotRequired[float]
    """The engine's figures, in a gear only."""
    engine_torque_nm: NotRequired[float]
    engine_power_w: NotRequired[float]
    fuel_rate_g_per_h: NotRequired[float]
    """NaN beyond the full-load curve's speeds."""
    brake_power_w: NotRequired[float]
    """At the wheels, beyond what the engine's drag takes [W]."""
    feasible: NotRequired[bool]

class _TruckFacts(TypedDict):
    gears: int
    rated_power_w: float
    """The most the full-load curve gives [W], at `rated_speed_rpm`."""
    rated_speed_rpm: float
    full_load_speed_range_rpm: list[float]
    """[lowest, highest] speed of the full-load curve [rpm]."""
    fuel_map_speed_range_rpm: list[float]
    fuel_map_torque_range_nm: list[float]
    gear_loss_maps: bool
    """Whether VECTO's loss maps give the gears' losses (else gear_efficiency and loss_torque_nm)."""
    axle_loss_map: bool
    efficiency: float
    """Driveline efficiency without loss maps, gearbox times axle [-]."""

class _EnginePoint(TypedDict):
    max_torque_nm: float
    """Full-load torque at the speed [Nm]."""
    drag_torque_nm: float
    """Drag torque at the speed [Nm] (negative)."""
    fuel_rate_g_per_h: float
    """Fuel rate [g/h]: 0 at or below the drag torque, the nearest boundary value outside the map."""
    in_fuel_map: bool
    """Whether the point lies inside the fuel map's convex hull."""

class _DrivelinePoint(TypedDict):
    gearbox_loss_w: float
    """Power the gearbox loses [W]."""
    retarder_loss_w: float
    """Power the retarder's drag takes [W] (0 without one)."""
    axle_loss_w: float
    """Power the axle loses [W]."""
    wheel_torque_nm: float
    """Torque at the wheels [Nm]."""

class _LevelData(Protocol):
    """One machine at one voltage [V]: torque limits (speed [rpm], most driving and most braking
    torque [Nm]) and power map (speed [rpm], torque [Nm], electric power [W])."""

    @property
    def voltage_v(self) -> float: ...
    @property
    def torque_limits(self) -> _Rows: ...
    @property
    def power_map(self) -> _Rows: ...

class _MachineData(Protocol):
    """`count` alike machines, one machine's inertia [kg m²], levels and drag curve (speed [rpm],
    drag torque [Nm])."""

    @property
    def count(self) -> int: ...
    @property
    def inertia_kgm2(self) -> float: ...
    @property
    def levels(self) -> Sequence[_LevelData]: ...
    @property
    def drag_curve(self) -> Sequence[tuple[float, float]]: ...

class _ReductionData(Protocol):
    """The reduction's ratio, loss map (input speed [rpm], input torque [Nm], loss [Nm]) and the
    tyres' dynamic radius [m]."""

    @property
    def ratio(self) -> float: ...
    @property
    def loss_map(self) -> _Rows | None: ...
    @property
    def wheel_radius_m(self) -> float: ...

class _BatteryData(Protocol):
    """Capacity [Ah]; open-circuit voltage, 20 s resistance [mΩ] and current limits [A] over the
    state of charge [%]; the declared usable window [%]."""

    @property
    def capacity_ah(self) -> float: ...
    @property
    def ocv(self) -> Sequence[tuple[float, float]]: ...
    @property
    def resistance_mohm(self) -> Sequence[tuple[float, float]]: ...
    @property
    def current_limits(self) -> _Rows: ...
    @property
    def soc_window_pct(self) -> tuple[float, float]: ...

class _ElectricFacts(TypedDict):
    gears: int
    max_torque_nm: float
    """The machines' most driving torque at standstill [Nm]."""
    peak_power_w: float
    """The most their torque limits give [W]."""
    top_speed_rpm: float
    reduction_ratio: float
    battery_ocv_v: float
    battery_resistance_ohm: float
    battery_max_discharge_w: float
    battery_max_charge_w: float
    soc_start_pct: float
    usable_window_pct: list[float]
    """Declaration mode's window, narrowed for ageing [%]."""
    usable_energy_kwh: float
    effective_mass_kg: float
    """Body, wheels and machines: the mass whose ½·m·v² the truck's kinetic energy is [kg]."""
    continuous_torque_nm: float | None
    """The machines' continuous torque, all of them, which they hold while derated [Nm]; None: not rated."""
    continuous_loss_w: float | None
    """Their loss at the continuous rating [W]."""
    overload_buffer_kj: float | None
    """The heat they may store above it before they derate [kJ]."""

class _ElectricState(TypedDict):
    pedal: float
    brake: float
    feasible: bool
    """Whether the machines and the battery give the torque (else the levels are clipped to 1)."""
    machine_speed_rpm: float
    machine_torque_nm: float
    battery_power_w: float
    """Drawn from the battery's store, negative where braking returns energy [W]."""
    battery_loss_w: float
    aux_power_w: float
    machine_loss_w: float
    reduction_loss_w: float
    wheel_power_w: float
    friction_brake_power_w: float

class _MachinePoint(TypedDict):
    electric_power_w: float
    """From the power map's triangulation of the loss torque, at the battery's voltage [W]."""
    loss_w: float
    max_drive_nm: float
    max_brake_nm: float
    drag_nm: float
    battery_current_a: float
    """The current giving that electric power at the terminals [A]."""
    battery_internal_w: float

@final
class MapTruck:
    """A truck from component data: engine, driveline, body, and its gearbox's traction interruption
    [s]; or a battery-electric truck (`MapTruck.electric`)."""

    def __new__(
        cls, engine: _EngineData, driveline: _DrivelineData, body: _BodyData, traction_interruption_s: float = 0.0
    ) -> MapTruck: ...
    @staticmethod
    def electric(
        machine: _MachineData,
        reduction: _ReductionData,
        battery: _BatteryData,
        body: _BodyData,
        conditioning_w: float,
        soc_start_pct: float | None,
    ) -> MapTruck:
        """A battery-electric truck; `soc_start_pct` None: the middle of the usable window."""
    @property
    def is_electric(self) -> bool: ...
    def machine_point(self, speed_rpm: float, torque_nm: float) -> _MachinePoint:
        """A battery-electric truck's machines together at `speed_rpm` and `torque_nm`."""
    def electric_state(self, v_mps: float, slope_rad: float, brake_torque_max_nm: float) -> _ElectricState:
        """A battery-electric truck holding `v_mps` (> 0) on `slope_rad`."""
    def electric_flows(
        self,
        v_mps: npt.NDArray[np.float64],
        pedal: npt.NDArray[np.float64],
        brake: npt.NDArray[np.float64],
        brake_torque_max_nm: float,
    ) -> dict[str, npt.NDArray[np.float64]]:
        """Where a battery-electric truck's power goes under each control [W]: battery_w,
        battery_loss_w, aux_w, machine_loss_w, reduction_loss_w, wheel_w, friction_brake_w."""
    @property
    def electric_facts(self) -> _ElectricFacts:
        """What the battery-electric truck is (ParamError for an engine-driven one)."""
    @property
    def facts(self) -> _TruckFacts:
        """What the truck is: gears, rated power, what its maps cover, which losses loss maps give."""
    def engine_point(self, speed_rpm: float, torque_nm: float) -> _EnginePoint:
        """The engine at `speed_rpm` and `torque_nm`."""
    def driveline_point(self, speed_rpm: float, torque_nm: float, gear: int) -> _DrivelinePoint:
        """The driveline in `gear` (1..=gears) at engine speed `speed_rpm` (> 0) with `torque_nm` at the
        gearbox input: each stage's lost power and the wheel torque."""
    def at(self, v_mps: float, acc_mps2: float = 0.0, slope_rad: float = 0.0, gear: int | None = None) -> _DrivingState:
        """The truck at `v_mps` (> 0), `acc_mps2` and `slope_rad`: its drag area and road loads, and in
        `gear` (1..=gears) the engine's operating point."""

class _CruiseData(Protocol):
    """The cruise keys that shape the band: v_ref, v_dec, v_inc and the target offset [km/h], the
    deceleration the top falls at [m/s²]."""

    @property
    def v_ref_kmh(self) -> float: ...
    @property
    def v_dec_kmh(self) -> float: ...
    @property
    def v_inc_kmh(self) -> float: ...
    @property
    def target_offset_kmh(self) -> float: ...
    @property
    def target_decel_mps2(self) -> float: ...

@final
class Road:
    """A road: points, the grade and (optionally) the target speed [km/h] of each segment; flat beyond the end."""

    def __new__(
        cls,
        distance_m: npt.NDArray[np.float64],
        slope: npt.NDArray[np.float64],
        target_speed_kmh: npt.NDArray[np.float64] | None = None,
    ) -> Road: ...
    def speed_band(
        self, distance_m: npt.NDArray[np.float64], cruise: _CruiseData
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """The band the controllers work to at each of `distance_m` [m] (increasing) for one cruise
        setting [km/h]: the stretch's set speed (without the top falling ahead of a lower one),
        v_min and v_max."""

_RunOutput: TypeAlias = tuple[dict[str, Any], dict[str, npt.NDArray[Any]]]
"""What a closed-loop run returns: its summary (figures by name, as `truckmpc.sim.simulate` documents)
and its trace (1-D arrays by column name, float64 but `gear` int64)."""

def run(
    settings: Settings,
    road: Road,
    altitude_m: npt.NDArray[np.float64],
    controller: str,
    controller_road: Road | None = None,
) -> _RunOutput:
    """Drive `road` with a built-in controller from its start to its end (or a stall), the closed
    loop in Rust with the GIL released.

    Args:
        settings: the run's settings and truck.
        road: the road; `altitude_m` gives the trace's altitude at each of its profile points [m].
        controller: a name of `controllers()`: "pi", "vecto_cc", "pcc", "mpc" or "optimal".
        controller_road: the road the controller plans on, if not `road` (the plant drives `road`).

    Returns:
        (summary, trace); the summary of a controller that solves the DP also holds its `settings`, with
        the resolved values under their declared names.
    """

def run_python(
    settings: Settings,
    road: Road,
    altitude_m: npt.NDArray[np.float64],
    controller: Any,
    profile: Any,
    state_type: Any,
) -> _RunOutput:
    """Drive `road` with a controller written in Python, in the same closed loop as the built-in ones.

    Args:
        settings: the run's settings and truck.
        road: the road; `altitude_m` gives the trace's altitude at each of its profile points [m].
        controller: an object of the `truckmpc.controller.Controller` protocol: `start(profile,
            state)` and `decide(state)` are called, the GIL held; the first exception ends the run
            and is re-raised.
        profile: the `RoadProfile` passed to `controller.start`.
        state_type: the class of the states passed (`truckmpc.controller.PlantState`).
    """

def controllers() -> list[tuple[str, str, bool]]:
    """The built-in controllers: (name, what it is, whether it solves the DP)."""
