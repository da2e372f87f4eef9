"""The generalisation section: which motions each held-out group tests on and which it trains on."""

import re

import pytest
import yaml

from tests.helpers import ROOT
from voxpose import workflow_config as wc
from voxpose.errors import VoxposeError

SHIPPED = yaml.safe_load((ROOT / "config/config.yaml").read_text())
QUICK = yaml.safe_load((ROOT / "config/quick.yaml").read_text())


def groups(**files) -> list:
    return [{"name": name, "files": patterns} for name, patterns in files.items()]


def resolve(section, names, sources=None, shipped=None):
    return wc.resolve_generalisation(section, names, "generalisation", sources or {}, shipped or {})


def test_a_derived_motion_follows_its_source_whatever_its_name():
    names = ["walk_s1_01", "walk_s2_01", "spiral_x", "spiral_x_turn090", "walk_s2_01_turn090"]
    # spiral_x was derived from s1's walk and its own turned copy from it: neither name says s1
    sources = {"spiral_x": "walk_s1_01", "spiral_x_turn090": "spiral_x", "walk_s2_01_turn090": "walk_s2_01"}
    section = {"train": ["*"], "groups": groups(s1=["*_s1_*"], s2=["*_s2_*"])}
    held_out, skipped = resolve(section, names, sources)
    s1 = ["spiral_x", "spiral_x_turn090", "walk_s1_01"]
    s2 = ["walk_s2_01", "walk_s2_01_turn090"]
    assert skipped == []
    assert held_out == {"s1": {"train": s2, "test_sets": {"s1": s1}, "test": s1},
                        "s2": {"train": s1, "test_sets": {"s2": s2}, "test": s2}}  # fmt: skip
    # without the sources, the spirals are in no group: always trained on, never tested
    held_out, _ = resolve(section, names)
    assert held_out["s1"]["test"] == ["walk_s1_01"] and "spiral_x" in held_out["s1"]["train"]


def test_a_motion_in_no_group_is_always_trained_on_and_the_pool_bounds_everything():
    names = ["walk_s1_01", "walk_s2_01", "jog_s3_01", "idle_s1_01"]
    section = {"train": ["walk_*", "jog_*"], "groups": groups(s1=["*_s1_*"], s2=["*_s2_*"])}
    held_out, _ = resolve(section, names)
    assert held_out["s1"] == {"train": ["jog_s3_01", "walk_s2_01"], "test_sets": {"s1": ["walk_s1_01"]},
                              "test": ["walk_s1_01"]}  # fmt: skip
    assert held_out["s2"]["train"] == ["jog_s3_01", "walk_s1_01"]  # idle_s1_01 is outside the pool


def test_a_motion_in_two_groups_is_refused_naming_the_key_and_both_groups():
    section = {"train": ["*"], "groups": groups(s1=["*_s1_*"], walks=["walk_*"])}
    message = "config key generalisation.groups.1.files: motion 'walk_s1_01' is in two groups, s1 and walks"
    with pytest.raises(VoxposeError, match=f"^{re.escape(message)}$"):
        resolve(section, ["walk_s1_01", "jog_s2_01"])


def test_an_empty_group_is_a_one_line_error_naming_the_key():
    section = {"train": ["walk_*"], "groups": groups(s1=["*_s1_*"], s4=["*_s4_*"], jogs=["jog_*"])}
    names = ["walk_s1_01", "walk_s2_01", "jog_s4_01"]  # s4's only motion is outside the pool
    message = ("config key generalisation.groups.1.files: group 's4' matches no motion of the pool "
               "(generalisation.train)")
    with pytest.raises(VoxposeError, match=f"^{re.escape(message)}$"):
        resolve(section, names)


def test_a_group_that_leaves_no_training_motion_and_a_repeated_name_are_refused():
    with pytest.raises(VoxposeError, match=r"^config key generalisation.groups.0.files: group 'all' leaves no trai"):
        resolve({"train": ["walk_*"], "groups": groups(all=["walk_*"])}, ["walk_a", "walk_b"])
    twice = {"train": ["*"], "groups": [{"name": "a", "files": ["walk_a"]}, {"name": "a", "files": ["walk_b"]}]}
    with pytest.raises(VoxposeError, match=r"^config key generalisation.groups.1.name: group 'a' is named twice$"):
        resolve(twice, ["walk_a", "walk_b", "jog_c"])


def test_the_shipped_section_leaves_out_groups_without_motions_on_other_data():
    section = SHIPPED["bvh_generalisation"]
    held_out, skipped = resolve(section, ["walk_cmu_02_01", "walk_cmu_08_01", "walk_lab_01"], shipped=section)
    assert list(held_out) == ["cmu_02", "cmu_08"]
    assert held_out["cmu_08"]["train"] == ["walk_cmu_02_01", "walk_lab_01"]
    assert skipped == ["cmu_01", "cmu_03", "cmu_05", "cmu_06", "cmu_07", "bandai1", "bandai2"]
    # no motion of the pool at all: every group left out, no error
    held_out, skipped = resolve(section, ["idle_lab_01"], shipped=section)
    assert held_out == {} and len(skipped) == 9
    # the user's own section keeps the errors (as an experiment's: a pattern that matches nothing)
    with pytest.raises(VoxposeError, match=r"^config key generalisation.train: pattern 'turnwalk_\*' matches no"):
        resolve(section, ["walk_cmu_02_01", "walk_cmu_08_01"], shipped={})


@pytest.mark.parametrize(("config", "held"), [(SHIPPED, "gen_02"), (QUICK, "gen_01")])
def test_on_the_generated_set_one_held_out_group_is_table2_and_shares_its_fit(config, held):
    names = wc.generated_motions(config["generated"])
    held_out, _ = resolve(config["generalisation"], names)
    table2 = wc.resolve_experiment("table2", config["experiments"]["table2"], names, "experiments")
    assert held_out[held]["train"] == table2["train"] and held_out[held]["test"] == table2["test"]
    assert wc.motion_set_tag(held_out[held]["train"]) == wc.motion_set_tag(table2["train"])
    assert len(held_out) == len(config["generalisation"]["groups"])


def _performer(name: str, derived: dict) -> str:
    """The performer of a shared motion from its source file's name: CMU subject or Bandai Namco set."""
    while name in derived:
        name = derived[name][1]
    found = re.search(r"_cmu_(\d\d)_|_(bandai[12])_", name)
    return f"cmu_{found[1]}" if found[1] else found[2]


def test_on_the_shared_data_no_performer_is_ever_trained_on_when_held_out(shared_bvh_dir):
    names = list(wc.bvh_dir_motions(shared_bvh_dir))
    derived, _ = wc.derived_motions(SHIPPED["derived"], names)
    section = SHIPPED["bvh_generalisation"]
    held_out, skipped = wc.resolve_generalisation(section, [*names, *derived], "bvh_generalisation",
                                                  {m: d[1] for m, d in derived.items()}, section)  # fmt: skip
    assert skipped == [] and list(held_out) == [g["name"] for g in section["groups"]]
    for group, exp in held_out.items():
        assert {_performer(m, derived) for m in exp["test"]} == {group}
        assert group not in {_performer(m, derived) for m in exp["train"]}
    # the derived spirals of subject 8 and the turned copies of subject 2's walk are tested with their subjects
    assert {"spiral_walk_cmu_08_01", "walk_cmu_08_01"} <= set(held_out["cmu_08"]["test"])
    assert "walk_cmu_02_01_turn090" in held_out["cmu_02"]["test"]


def test_the_schema_takes_groups_as_a_list_only():
    config = dict(SHIPPED, generalisation={"train": ["*"], "groups": {"gen_00": ["*_gen_00"]}})
    with pytest.raises(VoxposeError, match="^config key generalisation.groups: "):
        wc.validate_config(config)
    bad = dict(SHIPPED, generalisation={"train": ["*"], "groups": [{"name": "a/b", "files": ["x"]}]})
    with pytest.raises(VoxposeError, match="^config key generalisation.groups.0.name: "):
        wc.validate_config(bad)
