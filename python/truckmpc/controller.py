"""The contract between the closed-loop simulation and a cruise controller.

A controller is asked for a decision at the current plant state and answers with the inputs to apply
and how long to hold them:

* ``until_m is None`` -- for one plant step (``plant_dt_s``), then ask again. The PI controller of
  section 2.5 decides like this, as a sampled controller running at the plant step.
* ``until_m = s`` -- hold the inputs until the truck reaches distance ``s`` [m] (or the road's end),
  then ask again. A look-ahead controller that decides once per stage of S metres (chapter 5) uses
  this; the plant still integrates with its fine step underneath.

A controller may also offer ``summary() -> dict``; its entries join the run's summary.

The built-in PI and MPC implement the same contract in Rust and run in the Rust closed loop; a
controller written in Python runs in the Python loop of :func:`truckmpc.sim.simulate`, which steps the
same plant in the same way, so fuel and time figures are computed identically for all of them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple, Protocol

if TYPE_CHECKING:
    from truckmpc.roads import RoadProfile


class Control(NamedTuple):
    """Inputs held constant over a plant step or a stage."""

    pedal: float
    """Pedal level P in [0, 1] (normalised fueling)."""
    brake: float
    """Brake level B in [0, 1] (fraction of the maximum brake torque)."""
    gear: int
    """Gear number, 1 = lowest, 0 = neutral."""


class PlantState(NamedTuple):
    """State of the simulated truck; the integrals are cumulative since the start of the run."""

    s_m: float
    """Position along the road [m]."""
    v_mps: float
    """Speed [m/s]."""
    t_s: float
    """Elapsed time [s]."""
    fuel_g: float
    """Fuel used [g]; for a battery-electric truck, the net energy drawn from its battery [J]."""
    brake_energy_j: float
    """Energy dissipated in the service brakes [J]."""
    stalled: bool
    """The speed fell below the stall speed; the truck no longer moves."""


Decision = tuple[Control, "float | None"]
"""What :meth:`Controller.decide` returns: the inputs and ``until_m`` (None = one plant step)."""


class Controller(Protocol):
    """A cruise controller the closed-loop simulation can drive."""

    name: str
    """Short name used in outputs (``"pi"``, ``"mpc"``): summary key and ``trace-<name>.csv``."""

    def start(self, road: RoadProfile, state: PlantState) -> None:
        """Prepare for a run over ``road`` starting at ``state`` (resets any internal state)."""
        ...

    def decide(self, state: PlantState) -> Decision:
        """Inputs to apply from ``state`` on, and until when (see the module docstring)."""
        ...
