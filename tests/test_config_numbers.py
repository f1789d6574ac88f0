"""Numbers as users write them, in --set overrides and in config files."""

from __future__ import annotations

from pathlib import Path

from truckmpc import load_run_config


def test_a_number_with_an_exponent_is_a_number(tmp_path: Path) -> None:
    """1e5 and 1.5E6 are numbers in --set and in a config file (YAML 1.1 would read them as text)."""
    overlay = tmp_path / "weights.yaml"
    overlay.write_text("q_brake_per_km: 4e3\nq_neutral: 3.0E1\n")
    config = load_run_config(config_paths=[overlay], overrides=["q_gear_shift=6e1", "stage_m=2.5e1"])
    assert (config.mpc.q_brake_per_km, config.mpc.q_neutral) == (4000.0, 30.0)
    assert (config.mpc.q_gear_shift, config.mpc.stage_m) == (60.0, 25.0)
