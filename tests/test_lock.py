"""The pinned environment: ``requirements.lock`` pins every run and test dependency of ``pyproject.toml`` to one
version inside its range, with hashes, and the environment the tests run in is that one."""

import re
import tomllib
from importlib import metadata

from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

from tests.helpers import ROOT


def _lock() -> dict:
    """{name: (version, number of hashes)} of requirements.lock."""
    text = (ROOT / "requirements.lock").read_text()
    pins = {}
    for m in re.finditer(r"^([A-Za-z0-9_.-]+)==(\S+)((?:\s*\\\n\s+--hash=sha256:[0-9a-f]{64})*)", text, re.M):
        pins[canonicalize_name(m.group(1))] = (m.group(2), m.group(3).count("--hash="))
    return pins


def _declared():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    return [Requirement(r) for r in project["dependencies"] + project["optional-dependencies"]["test"]]


def test_every_dependency_is_pinned_in_its_range_with_hashes():
    pins = _lock()
    for req in _declared():
        version, hashes = pins[canonicalize_name(req.name)]
        assert req.specifier.contains(version, prereleases=True), (req, version)
        assert hashes >= 1, req.name
    assert all(hashes >= 1 for _, hashes in pins.values())


def test_the_environment_is_the_locked_one():
    """CI installs from the lock (README's test command): every locked distribution is installed at its pin."""
    wrong = {name: (version, metadata.version(name)) for name, (version, _) in _lock().items()
             if metadata.version(name) != version}  # fmt: skip
    assert wrong == {}, "installed versions differ from requirements.lock (pip install -r requirements.lock)"
