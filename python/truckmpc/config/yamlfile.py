"""Reading users' YAML files: a top-level mapping, no key given twice, and the line of every key."""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any

import yaml

from truckmpc.errors import ConfigError, read_user_text

PathLike = str | os.PathLike[str]


class _StrictLoader(yaml.SafeLoader):
    """Safe loader that rejects a key given twice in one mapping (PyYAML keeps the last silently)
    and any alias (``*name``): a config file has no use for them, and nested aliases expand
    exponentially (a "billion laughs")."""

    def compose_node(self, parent: yaml.Node | None, index: int) -> yaml.Node | None:
        if self.check_event(yaml.AliasEvent):
            event = self.peek_event()  # type: ignore[no-untyped-call]
            problem = f"found the alias *{event.anchor}: aliases are not accepted in a config file"
            raise yaml.composer.ComposerError(None, None, problem, event.start_mark)
        return super().compose_node(parent, index)

    def get_single_node(self) -> yaml.Node | None:
        try:
            return super().get_single_node()
        except RecursionError:  # PyYAML composes nested collections recursively
            raise yaml.YAMLError("nested too deeply") from None


def _construct_mapping(loader: _StrictLoader, node: yaml.MappingNode, deep: bool = False) -> dict[Any, Any]:
    seen: set[Any] = set()
    for key_node, _ in node.value:
        key = loader.construct_object(key_node, deep=deep)
        if not isinstance(key, str):
            continue
        if key in seen:
            raise yaml.constructor.ConstructorError(None, None, f"key {key!r} given twice", key_node.start_mark)
        seen.add(key)
    return loader.construct_mapping(node, deep=deep)


_StrictLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)
# YAML 1.1, which PyYAML follows, reads 1e5 and 1.5e6 (an exponent without a dot, or without a sign)
# as text; YAML 1.2 and every user read them as numbers.
_StrictLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9][0-9_]*)[eE][-+]?[0-9]+$"),
    list("-+0123456789."),
)


def display_path(path: Path) -> str:
    """How a file is named in messages: relative to the working directory when it is below it."""
    try:
        return str(path.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(path)


def read_mapping(path: PathLike) -> tuple[dict[str, Any], str, dict[str, int]]:
    """The top-level mapping of a YAML file, the file's display name and the line of each key."""
    where = display_path(Path(path))
    text = read_user_text(Path(path), where, "a YAML file", ConfigError)
    try:
        loader = _StrictLoader(text)  # raises on a control character
    except yaml.YAMLError as err:
        raise ConfigError(f"{where}: invalid YAML: {err}") from None
    try:
        node = loader.get_single_node()
        data = None if node is None else loader.construct_document(node)
    except yaml.MarkedYAMLError as err:
        line = f":{err.problem_mark.line + 1}" if err.problem_mark is not None else ""
        raise ConfigError(f"{where}{line}: invalid YAML: {err.problem or err.context}") from None
    except yaml.YAMLError as err:
        raise ConfigError(f"{where}: invalid YAML: {err}") from None
    finally:
        loader.dispose()
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise ConfigError(f"{where}: expected a mapping of key: value at the top level, got {type(data).__name__}")
    for key in data:
        if not isinstance(key, str):
            raise ConfigError(f"{where}: key {show_value(key)}: expected a text key")
    keys = [k for k, _ in node.value if isinstance(k, yaml.ScalarNode)] if isinstance(node, yaml.MappingNode) else []
    lines = {k.value: k.start_mark.line + 1 for k in keys}
    return data, where, lines


def show_value(value: Any) -> str:
    """A value as the user wrote it, briefly (YAML spelling for true, false and null)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if value is None:
        return "null"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def load_value(text: str) -> Any:
    """One YAML value (a `--set` value), with the same rules as a config file: no aliases, no key
    given twice. Raises `yaml.YAMLError`."""
    loader = _StrictLoader(text)
    try:
        return loader.get_single_data()
    finally:
        loader.dispose()


def parse_assignment(text: str, flag: str = "--set") -> tuple[str, Any]:
    """A ``key=value`` option (``--set``) as its key and its YAML value; errors name ``flag key``."""
    key, sep, raw = text.partition("=")
    key = key.strip()
    if not sep or not key:
        raise ConfigError(f"{flag} {text!r}: expected key=value")
    try:
        return key, load_value(raw)
    except yaml.YAMLError as err:
        problem = getattr(err, "problem", None) or str(err) or "syntax error"
        raise ConfigError(f"{flag} {key}: value {show_value(raw.strip())} is not valid YAML ({problem})") from None
