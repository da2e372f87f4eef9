"""Carving settings: the paper's defaults in one place, and refusal of what they cannot be."""

import pytest

from voxpose.errors import VoxposeError
from voxpose.voxels.settings import DEFAULTS, VoxelSettings


def test_defaults_are_the_papers():
    assert DEFAULTS.l_res_fraction == pytest.approx(1 / 60)  # l_res = h_sub / 60 (Section 4)
    assert DEFAULTS.n_basis == 200 and DEFAULTS.min_views is None  # Figure 2; strict intersection
    assert DEFAULTS.carving() == {"l_res_fraction": 1 / 60, "min_views": None, "n_basis": 200}


def test_from_config_takes_the_voxels_section_and_names_an_unknown_key():
    s = VoxelSettings.from_config({"l_res_fraction": 0.02, "min_views": 5, "proportions": None})
    assert s.carving() == {"l_res_fraction": 0.02, "min_views": 5, "n_basis": 200} and s.proportions == {}
    with pytest.raises(VoxposeError, match="--params: unknown key 'l_res'"):
        VoxelSettings.from_config({"l_res": 0.02}, "--params")


@pytest.mark.parametrize(
    "bad",
    [{"l_res_fraction": 0}, {"l_res_fraction": 1.5}, {"l_res_fraction": True}, {"min_views": 0},
     {"min_views": 2.5}, {"n_basis": 0}, {"n_basis": "200"}],
)  # fmt: skip
def test_impossible_values_are_refused(bad):
    with pytest.raises(VoxposeError, match=f"voxels: {next(iter(bad))}"):
        VoxelSettings(**bad)
