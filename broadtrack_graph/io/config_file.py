"""Option files (``--config FILE``, TOML): the fields of a frozen options dataclass as keys.

A field that is itself a dataclass is a TOML table (``[flow]`` for ``TrackingConfig.flow``);
keys left out keep their defaults. Unknown keys and values of the wrong type are a one-line
:class:`~broadtrack_graph.errors.InputError` naming the file and the key. Options given on the
command line override the file (:func:`read_config_file`'s ``overrides``).
"""

from __future__ import annotations

import dataclasses
import tomllib
import types
import typing
from pathlib import Path

from broadtrack_graph.errors import InputError

T = typing.TypeVar("T")


def read_config_file(path: str | Path | None, cls: type[T], overrides: dict | None = None) -> T:
    """Build ``cls`` from a TOML file, then apply ``overrides`` (top-level field -> value).

    Args:
        path: the TOML file, or None for the defaults of ``cls``.
        cls: a dataclass whose fields are bool, int, float, str, ``X | None``, ``tuple[X, ...]``
            or dataclasses of those.
        overrides: values that win over the file (e.g. command-line flags given explicitly).

    Raises:
        InputError: file missing or not TOML, an unknown key, a value of the wrong type, or a
            value the dataclass rejects (its ``__post_init__`` ValueError).
    """
    config = cls() if path is None else _build(cls, _load(Path(path)), Path(path), "")
    if overrides:
        try:
            config = dataclasses.replace(config, **overrides)
        except ValueError as exc:
            raise InputError(None, str(exc)) from None
    return config


def _load(path: Path) -> dict:
    try:
        with open(path, "rb") as handle:
            return tomllib.load(handle)
    except FileNotFoundError:
        raise InputError(path, "config file not found") from None
    except OSError as exc:
        raise InputError(path, f"cannot read: {exc.strerror or exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(path, f"not a TOML file: {exc}") from None


def _build(cls, data: dict, path: Path, prefix: str):
    hints = typing.get_type_hints(cls)
    names = [f.name for f in dataclasses.fields(cls)]
    kwargs = {}
    for key, value in data.items():
        name = prefix + key
        if key not in names:
            raise InputError(path, f"unknown key '{name}' (known: {', '.join(prefix + n for n in names)})")
        kind = hints[key]
        if dataclasses.is_dataclass(kind):
            if not isinstance(value, dict):
                raise InputError(path, f"key '{name}': expected a table [{name}], got {type(value).__name__}")
            kwargs[key] = _build(kind, value, path, name + ".")
        else:
            kwargs[key] = _value(value, kind, path, name)
    try:
        return cls(**kwargs)
    except ValueError as exc:
        raise InputError(path, str(exc)) from None


def _value(value, kind, path: Path, name: str):
    """``value`` checked against the annotation ``kind`` (ints are accepted as floats)."""
    converted = _convert(value, kind)
    if converted is _BAD:
        raise InputError(path, f"key '{name}': expected {_type_name(kind)}, got {type(value).__name__} {value!r}")
    return converted


_BAD = object()


def _convert(value, kind):
    origin = typing.get_origin(kind)
    if origin in (typing.Union, types.UnionType):
        for member in typing.get_args(kind):
            if member is not type(None):
                converted = _convert(value, member)
                if converted is not _BAD:
                    return converted
        return _BAD
    if origin is tuple:
        args = typing.get_args(kind)
        if not isinstance(value, list) or len(args) != 2 or args[1] is not Ellipsis:
            return _BAD
        items = [_convert(item, args[0]) for item in value]
        return _BAD if any(item is _BAD for item in items) else tuple(items)
    if kind is bool:
        return value if isinstance(value, bool) else _BAD
    if kind is int:
        return value if isinstance(value, int) and not isinstance(value, bool) else _BAD
    if kind is float:
        return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else _BAD
    if kind is str:
        return value if isinstance(value, str) else _BAD
    return _BAD


def _type_name(kind) -> str:
    if typing.get_origin(kind) in (typing.Union, types.UnionType):
        return " or ".join(_type_name(k) for k in typing.get_args(kind) if k is not type(None))
    if typing.get_origin(kind) is tuple:
        return f"a list of {_type_name(typing.get_args(kind)[0])}"
    return {bool: "true or false", int: "an integer", float: "a number", str: "a string"}.get(kind, str(kind))
