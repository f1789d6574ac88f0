"""Configuration: every parameter declared once in the Rust core, read here from YAML files and
`--set` overrides, and validated once, by the core.

See :mod:`truckmpc.config.run_config` for the layers and :mod:`truckmpc.config.keys` for the keys.
"""

from truckmpc.config.docs import (
    KEY_COLUMNS,
    defaults_yaml,
    key_rows,
    key_table,
    packaged_defaults,
    rewrite_key_tables,
    write_packaged_defaults,
)
from truckmpc.config.keys import (
    KEYS,
    SECTION_NAMES,
    SPEC_BY_KEY,
    SPECS,
    VEHICLE_KEYS,
    default_config_path,
    section_keys,
)
from truckmpc.config.run_config import Origin, RunConfig, Section, config_from_values, load_run_config
from truckmpc.errors import ConfigError

__all__ = [
    "KEYS",
    "KEY_COLUMNS",
    "SECTION_NAMES",
    "SPECS",
    "SPEC_BY_KEY",
    "VEHICLE_KEYS",
    "ConfigError",
    "Origin",
    "RunConfig",
    "Section",
    "config_from_values",
    "default_config_path",
    "defaults_yaml",
    "key_rows",
    "key_table",
    "load_run_config",
    "packaged_defaults",
    "rewrite_key_tables",
    "section_keys",
    "write_packaged_defaults",
]
