"""Reading the project's versioned JSON files: one place for the checks every format shares.

A file is read only if it is a regular file of at most MAX_BYTES, parsed without NaN or Infinity and
with no integer longer than MAX_DIGITS, and then validated whole against its format's JSON Schema
(fastjsonschema), so a refusal names the first offending field by its JSON path (`lights[2].position:
expected 2 numbers, got 4`). The schemas bound every string's length, every list's count and every
number's range; the model's own constructors then check what the values mean."""
from __future__ import annotations

import json
import os
from collections.abc import Callable, Iterable

import fastjsonschema
from fastjsonschema import JsonSchemaValueException

from app.io.regular_file import read_regular_bytes

MAX_BYTES = 8 << 20  # 150,000 points as the editor saves them; parsing a hostile file this size peaks near 140 MB
MAX_DIGITS = 40  # an integer literal longer than this is no coordinate or count (and Python caps them at 4300)
MAX_MAGNITUDE = 1e6  # world units and radians: far beyond any view, and float32 still resolves 1/8 of a unit


class _Refused(ValueError):
    """A literal the parser refuses (NaN, Infinity, too many digits)."""


def _parse_int(text: str) -> int:
    digits = len(text.lstrip("-"))
    if digits > MAX_DIGITS:
        raise _Refused(f"an integer of {digits} digits")
    return int(text)


def _parse_constant(name: str):
    raise _Refused(f"{name} is not a finite number")


def storable(what: str, *values: float) -> None:
    """Refuse numbers no scene file holds, so that whatever a command makes, a save loads again."""
    if any(abs(v) > MAX_MAGNITUDE for v in values):
        raise ValueError(f"{what} must be within -{MAX_MAGNITUDE:g}..{MAX_MAGNITUDE:g}")


Validator = Callable[[dict], dict]


class JSONFileError(ValueError):
    """A file that is no JSON this project reads (format_name's refusal)."""


def _parsed(path: str | os.PathLike, error: type[Exception]):
    """The file's JSON value, read within the limits; otherwise `error` saying why (the path first)."""
    try:
        raw = read_regular_bytes(path, MAX_BYTES)
    except OSError as exc:
        raise error(f"cannot read {path}: {exc.strerror}") from None
    try:
        # A float that overflows to inf needs no hook: every number in a schema has a range that refuses it.
        return json.loads(raw.decode("utf-8"), parse_int=_parse_int, parse_constant=_parse_constant)
    except RecursionError:  # the C parser recurses once per bracket
        raise error(f"{path} is not valid JSON: nested too deeply") from None
    except ValueError as exc:  # JSONDecodeError, UnicodeDecodeError and _Refused are ValueErrors
        raise error(f"{path} is not valid JSON: {exc}") from None


def format_name(path: str | os.PathLike) -> str | None:
    """The "format" a JSON file names ("shadelab.lighting2d"), which tells the workspaces' files apart; None if
    it names none. JSONFileError if it cannot be read or parsed."""
    data = _parsed(path, JSONFileError)
    name = data.get("format") if isinstance(data, dict) else None
    return name if isinstance(name, str) else None


def read_versioned(path: str | os.PathLike, fmt: str, version: int, error: type[Exception],
                   validator: Validator) -> dict:
    """The file's object, once it parsed, names `fmt` at `version` and passed `validator`; otherwise
    `error` saying why (the path first)."""
    data = _parsed(path, error)
    if not isinstance(data, dict) or data.get("format") != fmt:
        raise error(f"{path} is not a {fmt} file")
    if data.get("version") != version:
        raise error(f"{path}: unsupported version {_short(data.get('version'))} (this build reads {version})")
    try:
        validator(data)  # stops at the first problem, counts checked before items
    except JsonSchemaValueException as problem:
        raise error(f"{path}: {_where(problem.name)}: {_say(problem)}") from None
    return data


# ---- schema pieces the formats share -------------------------------------------------------------


def validator(properties: dict, required: Iterable[str] = ()) -> Validator:
    """A validator for a versioned file: `properties` besides format and version, nothing else. Compiled
    to Python once (fastjsonschema), so an 8 MiB scene validates in well under a second."""
    return fastjsonschema.compile(obj({"format": {"type": "string"}, "version": {"type": "integer"}, **properties},
                                      required))


def obj(properties: dict, required: Iterable[str] = ()) -> dict:
    return {"type": "object", "properties": properties, "required": list(required), "additionalProperties": False}


def number(lo: float = -MAX_MAGNITUDE, hi: float = MAX_MAGNITUDE, above: float | None = None) -> dict:
    """A number within lo..hi; `above` instead of lo when the bound itself is refused (a radius > 0)."""
    low = {"minimum": lo} if above is None else {"exclusiveMinimum": above}
    return {"type": "number", **low, "maximum": hi}


def array(items: dict, at_most: int, at_least: int = 0, title: str | None = None) -> dict:
    """A list of `items`; `title` names them in messages ("points")."""
    return {"type": "array", "items": items, "minItems": at_least, "maxItems": at_most,
            **({"title": title} if title else {})}


def numbers(count: int, item: dict | None = None) -> dict:
    return array(item or number(), count, count)


def text(at_most: int) -> dict:
    return {"type": "string", "minLength": 1, "maxLength": at_most}


# ---- messages --------------------------------------------------------------------------------------

_JSON_TYPES = {"object": "an object", "array": "a list", "string": "a string", "number": "a number",
               "integer": "a whole number", "boolean": "true or false", "null": "null"}
_NOUNS = {"number": "numbers", "integer": "whole numbers", "object": "objects", "array": "lists", "string": "strings"}


def _where(name: str) -> str:
    """fastjsonschema's 'data.lights[2].position' -> 'lights[2].position'. Only keys the schema names
    appear in it (an unknown key is the problem of the object holding it), so it needs no escaping."""
    return name.removeprefix("data").removeprefix(".") or "(top level)"


def _short(value, quote: bool = True, limit: int = 40) -> str:
    """A value for a message, cut short: an attacker's key or string must not flood the console."""
    text = repr(value) if quote else str(value)
    return text if len(text) <= limit else text[:limit] + "..."


def _json_type(value) -> str:
    for name, kinds in (("null", type(None)), ("boolean", bool), ("number", (int, float)), ("string", str),
                        ("array", list), ("object", dict)):
        if isinstance(value, kinds):
            return name
    return type(value).__name__


def _say(problem: JsonSchemaValueException) -> str:
    kind, want, got, schema = problem.rule, problem.rule_definition, problem.value, problem.definition
    if kind == "type":
        wanted = " or ".join(_JSON_TYPES[t] for t in ([want] if isinstance(want, str) else want))
        return f"expected {wanted}, got {_JSON_TYPES.get(_json_type(got), _json_type(got))}"
    if kind in ("minItems", "maxItems"):
        lo, hi = schema["minItems"], schema["maxItems"]
        noun = schema.get("title") or _NOUNS.get(schema["items"].get("type"), "items")
        count = str(lo) if lo == hi else (f"at most {hi}" if lo == 0 else f"{lo} to {hi}")
        return f"expected {count} {noun}, got {len(got)}"
    if kind in ("minimum", "maximum", "exclusiveMinimum"):
        low = (f"> {schema['exclusiveMinimum']:g} and <= " if "exclusiveMinimum" in schema
               else f"within {schema['minimum']:g}..")
        return f"must be {low}{schema['maximum']:g}, got {_short(got)}"
    if kind in ("minLength", "maxLength"):
        return f"expected {schema['minLength']} to {schema['maxLength']} characters, got {len(got)}"
    if kind == "additionalProperties":
        extra = sorted(set(got) - set(schema["properties"]))
        return f"unknown keys: {', '.join(_short(k, quote=False) for k in extra[:5])}"
    if kind == "required":
        return f"missing {', '.join(k for k in want if k not in got)}"
    if kind == "enum":
        return f"must be one of {', '.join(map(str, want))}, got {_short(got)}"
    return _short(problem.message, quote=False, limit=200)
