"""Descriptor settings: the paper's 3D shape context, its results tag, and refusal of unknown keys."""

import pytest

from voxpose.descriptors.settings import DescriptorSettings
from voxpose.errors import VoxposeError


def test_defaults_are_the_papers_descriptor():
    s = DescriptorSettings()
    assert (s.n_r, s.n_e, s.n_a) == (4, 5, 10) and s.n_r * s.n_e * s.n_a == 200  # Section 4
    assert s.r_min == 2.0 and s.r_max == pytest.approx(1 / 3) and s.soft and not s.normalise


@pytest.mark.parametrize(
    ("changes", "tag"),
    [
        ({}, "R0.3333-r2-4x5x10-soft"),
        ({"r_max": 0.2, "n_r": 3}, "R0.2-r2-3x5x10-soft"),
        ({"soft": False, "normalise": True, "r_min": 1.5}, "R0.3333-r1.5-4x5x10-hard-norm"),
    ],
)
def test_tag_names_every_setting(changes, tag):
    assert DescriptorSettings(**changes).tag() == tag


def test_tags_of_different_settings_differ():
    variants = [{}, {"n_r": 3}, {"n_e": 4}, {"n_a": 8}, {"r_min": 1.0}, {"r_max": 0.3}, {"soft": False},
                {"normalise": True}]  # fmt: skip
    assert len({DescriptorSettings(**v).tag() for v in variants}) == len(variants)


def test_an_unknown_key_is_named():
    with pytest.raises(VoxposeError, match="descriptor: unknown key 'bogus'"):
        DescriptorSettings.from_config({"bogus": 1})
