"""The config's JSON schema (``config_schema.yaml``, JSON Schema 2020-12) and the one validation that the
workflow's config and every command's JSON parameters go through (issue 21).

A command's ``--params`` take the keys of a config section, so they are checked by that section's schema
(``section``): the same keys, types and bounds, one schema for both. A value is refused with one line
naming the key. One leniency: PyYAML reads YAML 1.1, where ``1e-3`` (no dot) is a string, not a number, and
``config/README.md`` writes defaults that way; a string that JSON and YAML 1.2 read as a number is taken as
that number wherever the schema asks for a number (``_number_strings``), so ``tol: 1e-3`` means 0.001.
"""

import copy
import functools
import math
import re
from pathlib import Path

import jsonschema
import yaml

from voxpose.errors import VoxposeError

SCHEMA_PATH = Path(__file__).with_name("config_schema.yaml")

# a number as JSON and YAML 1.2 write it (PyYAML's YAML 1.1 leaves "1e-3" and "1E5" strings)
_NUMBER = re.compile(r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?")


@functools.cache
def _schema() -> dict:
    # libyaml's loader when PyYAML has it: every command reads the schema, 40 ms in pure Python, 4 with libyaml
    return yaml.load(SCHEMA_PATH.read_text(), Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))  # noqa: S506


def load_yaml(path):
    """A YAML file's content; a ``VoxposeError`` ``"path:line: not valid YAML: ..."`` naming where it breaks."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as err:
        raise VoxposeError(f"{path}: cannot read: {err.strerror or err}") from None
    except UnicodeDecodeError as err:
        raise VoxposeError(f"{path}: not UTF-8 text (byte {err.start})") from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as err:
        mark, start = getattr(err, "problem_mark", None), getattr(err, "context_mark", None)
        mark = mark or start
        where = f"{path}:{mark.line + 1}" if mark else str(path)
        context = getattr(err, "context", None)
        if context and start and start.line != mark.line:
            context += f" (from line {start.line + 1})"  # e.g. the line of an unclosed bracket
        problem = " ".join(filter(None, (context, getattr(err, "problem", None))))
        raise VoxposeError(f"{where}: not valid YAML: {problem or str(err).splitlines()[0]}") from None


def merge(base: dict, override: dict) -> dict:
    """``override`` merged onto a copy of ``base`` as Snakemake merges ``--configfile`` files: nested mappings
    merge, every other value (lists too) replaces."""
    out = copy.deepcopy(base)
    for key, value in override.items():
        out[key] = merge(out[key], value) if isinstance(value, dict) and isinstance(out.get(key), dict) else value
    return out


def config_schema() -> dict:
    """The whole config's schema (a copy)."""
    return copy.deepcopy(_schema())


def section(*path: str, required=True, drop=()) -> dict:
    """The schema of config section ``path`` (``"claims", "at"``), for parameters that take its keys.

    ``required=False`` when the command has a default for every key (``voxpose describe``), or the keys the
    command reads (the others stay allowed, not required: ``voxpose fit-features`` of one method); ``drop``:
    keys the section has that the command does not take (``motions.overrides``, resolved before the command).
    """
    root = config_schema()
    sub = root
    for key in path:
        sub = sub["properties"][key]
    sub = dict(sub)
    if required is False:
        sub.pop("required", None)
    elif required is not True:
        sub["required"] = [k for k in sub.get("required", []) if k in required]
    sub["properties"] = {k: v for k, v in sub["properties"].items() if k not in drop}
    return sub | {"$defs": root["$defs"]}


def _types(error) -> list:
    return error.validator_value if isinstance(error.validator_value, list) else [error.validator_value]


def _expects_number(error) -> bool:
    return "number" in _types(error) or "integer" in _types(error)


def _number_strings(validator, value) -> None:
    """Replace, in place, every string that reads as a finite number where the schema expects a number (also
    inside ``oneOf``/``anyOf`` alternatives)."""
    stack = list(validator.iter_errors(value))
    while stack:
        error = stack.pop()
        stack.extend(error.context or ())
        text = error.instance
        if error.validator != "type" or not isinstance(text, str) or not _NUMBER.fullmatch(text.strip()):
            continue
        if not _expects_number(error) or not error.absolute_path:
            continue
        *parents, last = error.absolute_path
        container = value
        for key in parents:
            container = container[key]
        number = float(text)
        if container[last] is text and math.isfinite(number):
            integral = number.is_integer() and ("number" not in _types(error) or re.fullmatch(r"[-+]?\d+", text))
            container[last] = int(number) if integral else number


def _message(error) -> str:
    if error.validator == "additionalProperties":
        known = sorted(error.schema.get("properties", {}))
        unknown = sorted(set(error.instance) - set(known))
        return f"unknown key {unknown[0]!r} (known: {', '.join(known)})"
    if error.validator == "type" and isinstance(error.instance, str) and _expects_number(error):
        return f"{error.instance!r} is not a number (a number is written like 0.001 or 1.0e-3)"
    return error.message


def validate(value, schema: dict, what: str) -> None:
    """Check ``value`` against ``schema``; a ``VoxposeError`` ``"<what> key a.b: ..."`` naming the first bad key.

    Number-like strings where the schema wants numbers are replaced by their numbers first, in place.
    """
    validator = jsonschema.Draft202012Validator(schema)
    _number_strings(validator, value)
    errors = sorted(validator.iter_errors(value), key=lambda e: [str(p) for p in e.absolute_path])
    if errors:
        err = errors[0]
        key = ".".join(str(p) for p in err.absolute_path)
        raise VoxposeError(f"{what} key {key}: {_message(err)}" if key else f"{what}: {_message(err)}")
