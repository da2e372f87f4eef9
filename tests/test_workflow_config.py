"""The workflow's view of the config: validation, motion lists, experiments, parameter-set tags."""

import re

import numpy as np
import pytest
import yaml

from tests.helpers import ROOT
from voxpose import workflow_config as wc
from voxpose.config_schema import merge
from voxpose.errors import VoxposeError
from voxpose.motion.data import kind_of


@pytest.fixture
def config():
    return yaml.safe_load((ROOT / "config" / "config.yaml").read_text())


_merge = merge  # Snakemake's --configfile semantics: nested dicts merge, other values replace


@pytest.mark.parametrize("name", ["config.yaml", "quick.yaml"])
def test_shipped_configs_are_valid(name, config):
    wc.validate_config(_merge(config, yaml.safe_load((ROOT / "config" / name).read_text())))


@pytest.mark.parametrize(
    ("path", "value", "key"),
    [
        (("descriptor", "n_r"), 0, "descriptor.n_r"),
        (("descriptor", "r_max"), 2.0, "descriptor.r_max"),
        (("features", "n_components"), "many", "features.n_components"),
        (("rig", "n_cameras"), 1, "rig.n_cameras"),
        (("figure4", "n_r"), [4, 0], "figure4.n_r.1"),
        (("regression", "pca_variance"), 1.5, "regression.pca_variance"),
        (("motions", "overrides"), [{"files": ["lab_*"], "jointmap": {}}], "motions.overrides.0"),  # misspelt
        (("motions", "overrides"), [{"unit_scale": 0.01}], "motions.overrides.0"),  # no files
        (("motions", "overrides"), [{"files": ["lab_*"]}], "motions.overrides.0"),  # changes nothing
        (("motions", "overrides"), [{"files": "lab_*", "fps": 24}], "motions.overrides.0.files"),
        (("motions", "overrides"), [{"files": ["a"], "drop_reference_frame": "yes"}],
         "motions.overrides.0.drop_reference_frame"),  # fmt: skip
        (("motions", "joint_map"), {"root": "pelvis"}, "motions.joint_map"),  # the 14 joints are required
    ],
)
def test_out_of_schema_value_names_the_key(config, path, value, key):
    node = config
    for p in path[:-1]:
        node = node[p]
    node[path[-1]] = value
    with pytest.raises(VoxposeError, match=rf"^config key {key}: "):
        wc.validate_config(config)


def test_unknown_key_is_refused(config):
    config["descriptor"]["n_rr"] = 4
    with pytest.raises(VoxposeError, match="config key descriptor: .*n_rr"):
        wc.validate_config(config)


MOTIONS = {"fps": 30.0, "unit_scale": None, "drop_reference_frame": "auto", "joint_map": None}


def test_motion_settings_take_the_first_matching_override():
    lab_map = {"root": "hip"}
    motions = MOTIONS | {
        "overrides": [
            {"files": ["walk_lab_*", "idle_*"], "unit_scale": 0.01, "joint_map": lab_map},
            {"files": ["idle_*"], "fps": 24.0, "drop_reference_frame": False},
        ]
    }
    assert wc.motion_settings("walk_cmu_02_01", motions) == MOTIONS  # no entry matches: the section's keys
    assert wc.motion_settings("walk_lab_3", motions) == MOTIONS | {"unit_scale": 0.01, "joint_map": lab_map}
    assert wc.motion_settings("idle_x", motions) == MOTIONS | {"unit_scale": 0.01, "joint_map": lab_map}  # first
    assert wc.motion_settings("walk_lab_3", MOTIONS) == MOTIONS  # no overrides at all
    motions["overrides"].reverse()
    assert wc.motion_settings("idle_x", motions) == MOTIONS | {"fps": 24.0, "drop_reference_frame": False}


def test_the_shipped_reactidle_entry_maps_only_reactidle_files(config):
    idle = wc.motion_settings("idle_reactidle_000_genuine", config["motions"])
    assert idle["unit_scale"] == 1.0 and idle["joint_map"]["lwrist"] == "forearm.L/end"
    for name in ("walk_cmu_02_01", "walk_bandai1_walk_normal_001", "walk_gen_00", "idle_bandai_x"):
        assert wc.motion_settings(name, config["motions"]) == MOTIONS


def test_generated_names_and_kinds():
    names = wc.generated_motions({"walk": [100, 120], "jump": [50]})
    assert names == {
        "walk_gen_00": ("walk", 0, 100),
        "walk_gen_01": ("walk", 1, 120),
        "jump_gen_00": ("jump", 0, 50),
    }
    assert kind_of("irregularwalk_cmu_03_01") == "irregularwalk"
    assert kind_of("spiral_walk_cmu_08_01") == "spiral"


def test_experiment_resolution():
    names = ["walk_a", "walk_b", "jog_a", "spiral_x", "spiral_y"]
    exp = wc.resolve_experiment(
        "t", {"train": ["walk_*", "jog_*"], "test": ["spiral_*"], "exclude": ["walk_b"]}, names, "experiments"
    )
    assert exp == {"train": ["jog_a", "walk_a"], "test": ["spiral_x", "spiral_y"],
                   "test_sets": {"test": ["spiral_x", "spiral_y"]}}  # fmt: skip


def test_named_test_sets_resolve_each_and_refuse_overlap_naming_the_set():
    names = ["walk_a", "walk_b", "jog_a", "spiral_x", "spiral_y"]
    spec = {"train": ["walk_a"], "test": {"spirals": ["spiral_*"], "other": ["jog_a", "walk_b", "spiral_x"]}}
    exp = wc.resolve_experiment("t", spec, names, "experiments")
    assert exp["test_sets"] == {"spirals": ["spiral_x", "spiral_y"], "other": ["jog_a", "spiral_x", "walk_b"]}
    assert exp["test"] == ["spiral_x", "spiral_y", "jog_a", "walk_b"]  # every test motion once, in set order
    bad = {"train": ["walk_*"], "test": {"spirals": ["spiral_*"], "mixed": ["walk_b"]}}
    with pytest.raises(VoxposeError, match="config key experiments.t.test.mixed: test motions also in training"):
        wc.resolve_experiment("t", bad, names, "experiments")
    with pytest.raises(VoxposeError, match=r"config key experiments.t.test.runs: pattern 'run_\*' matches no"):
        wc.resolve_experiment("t", {"train": ["walk_a"], "test": {"runs": ["run_*"]}}, names, "experiments")


def test_a_motion_set_tag_depends_on_the_motions_only():
    tag = wc.motion_set_tag(["walk_a", "jog_a"])
    assert tag == wc.motion_set_tag(["jog_a", "walk_a"]) and tag.startswith("n2-")
    assert tag != wc.motion_set_tag(["walk_a", "jog_b"]) and tag != wc.motion_set_tag(["walk_a"])


def test_named_test_sets_pass_the_schema_and_bad_set_names_do_not():
    config = yaml.safe_load((ROOT / "config/config.yaml").read_text())
    config["experiments"]["table2"]["test"] = {"walks": ["walk_*"], "rest": ["jog_*"]}
    wc.validate_config(config)
    config["experiments"]["table2"]["test"] = {"a/b": ["walk_*"]}
    with pytest.raises(VoxposeError, match="config key experiments.table2.test"):
        wc.validate_config(config)


def test_overlapping_experiment_is_refused_naming_the_files():
    names = ["walk_a", "walk_b", "spiral_x"]
    with pytest.raises(VoxposeError, match=r"config key experiments.t: test motions also in training: walk_b"):
        wc.resolve_experiment("t", {"train": ["walk_*"], "test": ["walk_b", "spiral_*"]}, names, "experiments")


def test_pattern_matching_nothing_names_the_key():
    with pytest.raises(VoxposeError, match=r"config key experiments.t.test: pattern 'run_\*' matches no motion"):
        wc.resolve_experiment("t", {"train": ["walk_*"], "test": ["run_*"]}, ["walk_a"], "experiments")


def test_bvh_dir_errors(tmp_path):
    with pytest.raises(VoxposeError, match="config key bvh_dir: no .bvh files"):
        wc.bvh_dir_motions(tmp_path)
    with pytest.raises(VoxposeError, match="config key bvh_dir: .* is not a folder"):
        wc.bvh_dir_motions(tmp_path / "missing")
    (tmp_path / "walk_x.bvh").write_text("")
    assert list(wc.bvh_dir_motions(tmp_path)) == ["walk_x"]


def test_bvh_dir_may_be_a_list_of_folders(tmp_path):
    for folder, names in {"a": ["walk_x", "jog_y"], "b": ["idle_z"], "c": ["walk_x"]}.items():
        (tmp_path / folder).mkdir()
        for name in names:
            (tmp_path / folder / f"{name}.bvh").write_text("")
    both = wc.bvh_dir_motions([tmp_path / "a", tmp_path / "b"])
    assert both == {"jog_y": tmp_path / "a/jog_y.bvh", "walk_x": tmp_path / "a/walk_x.bvh",
                    "idle_z": tmp_path / "b/idle_z.bvh"}  # fmt: skip
    first, second = tmp_path / "a/walk_x.bvh", tmp_path / "c/walk_x.bvh"
    twice = f"config key bvh_dir.1: motion 'walk_x' is in two folders: {first} and {second}"
    with pytest.raises(VoxposeError, match=f"^{re.escape(twice)}$"):
        wc.bvh_dir_motions([tmp_path / "a", tmp_path / "c"])
    with pytest.raises(VoxposeError, match="^config key bvh_dir.1: .*missing is not a folder"):
        wc.bvh_dir_motions([tmp_path / "a", tmp_path / "missing"])


@pytest.mark.parametrize(
    ("value", "ok"), [(None, True), ("../bvh", True), (["a", "b"], True), ([], False), ("", False), (3, False)]
)
def test_bvh_dir_schema(config, value, ok):
    config["bvh_dir"] = value
    if ok:
        wc.validate_config(config)
    else:
        with pytest.raises(VoxposeError, match="^config key bvh_dir: "):
            wc.validate_config(config)


def test_derived_motions_and_absent_sources():
    assert wc.derived_motions([{"kind": "spiral", "source": "walk_a"}], ["walk_a"]) == (
        {"spiral_walk_a": ("spiral", "walk_a", {})},
        [],
    )
    turn = wc.derived_motions([{"kind": "turn", "source": "jog_b", "degrees": 90}], ["jog_b"])
    assert turn == ({"jog_b_turn090": ("turn", "jog_b", {"degrees": 90})}, [])
    with pytest.raises(VoxposeError, match=r"derived.0: a turn needs 'degrees'"):
        wc.derived_motions([{"kind": "turn", "source": "jog_b"}], ["jog_b"])
    # a source not in bvh_dir (the shipped list names the shared walks): left out, and named
    items = [{"kind": "spiral", "source": "walk_z"}, {"kind": "drunk", "source": "walk_a"},
             {"kind": "turn", "source": "walk_z", "degrees": 45}]  # fmt: skip
    assert wc.derived_motions(items, ["walk_a"]) == (
        {"drunk_walk_a": ("drunk", "walk_a", {})},
        ["spiral_walk_z", "walk_z_turn045"],
    )


SHIPPED = {
    "table1": {"train": ["walk_*", "jog_*"], "exclude": ["walk_s8_*"], "test": ["spiral_walk_s8_*"]},
    "figure4": {"train": ["walk_s2_01", "jog_b_01"], "test": ["walk_s5_*", "turnwalk_*"]},
}


def test_a_shipped_experiment_without_motions_is_skipped():
    names = ["walk_s2_01", "walk_s5_01", "walk_s8_01", "turnwalk_c"]
    experiments, skipped = wc.resolve_experiments(SHIPPED, names, "bvh_experiments", SHIPPED)
    assert skipped == ["table1"]  # no spiral to test on
    # figure4 keeps the patterns that match (jog_b_01 is absent): no error
    test = ["turnwalk_c", "walk_s5_01"]
    assert experiments == {"figure4": {"train": ["walk_s2_01"], "test_sets": {"test": test}, "test": test}}
    # a named test set none of whose patterns match is left out with them
    named = {"figure4": SHIPPED["figure4"] | {"test": {"held_out": ["walk_s5_*"], "spirals": ["spiral_*"]}}}
    experiments, skipped = wc.resolve_experiments(named, names, "bvh_experiments", named)
    assert skipped == [] and experiments["figure4"]["test_sets"] == {"held_out": ["walk_s5_01"]}
    # training motions that are all excluded count as none
    _, skipped = wc.resolve_experiments(SHIPPED, ["walk_s8_01", "spiral_walk_s8_01"], "bvh_experiments", SHIPPED)
    assert skipped == ["table1", "figure4"]


def test_the_users_own_experiment_keeps_the_strict_rules():
    names = ["walk_s2_01", "walk_s5_01", "turnwalk_c"]
    own = {"figure4": {"train": ["walk_s2_01", "jog_b_01"], "test": ["walk_s5_*"]}}  # differs from the shipped one
    with pytest.raises(VoxposeError, match=r"^config key bvh_experiments.figure4.train: pattern 'jog_b_01' matches no"):
        wc.resolve_experiments(own, names, "bvh_experiments", SHIPPED)
    own = {"table1": {"train": ["walk_*"], "test": ["spiral_*"]}}
    with pytest.raises(VoxposeError, match=r"^config key bvh_experiments.table1.test: pattern 'spiral_\*' matches no"):
        wc.resolve_experiments(own, names, "bvh_experiments", SHIPPED)


def test_tags_distinguish_parameter_sets(config):
    d = config["descriptor"]
    tags = {wc.descriptor_tag(dict(d, r_max=r)) for r in (0.2, 0.267, 0.333333333333, 0.4)}
    assert len(tags) == 4
    assert wc.descriptor_tag(d) == "R0.3333-r2-4x5x10-soft-body"
    assert wc.descriptor_tag(dict(d, frame="world")) == "R0.3333-r2-4x5x10-soft"
    assert wc.feature_tag("mppca", config["features"]) == "mppca-K200-q5"
    assert wc.feature_tag("kmeans", config["features"]) == "kmeans-K200-n5"


def test_a_changed_rig_that_keeps_its_name_is_refused(tmp_path):
    from voxpose.voxels.cameras import rig_from_config, save_rig

    section = {"name": "ring", "file": None, "n_cameras": 4, "radius": 4.0, "height": 2.0, "target_height": 1.0,
               "focal_px": 300.0, "width": 120, "image_height": 100}  # fmt: skip
    wc.check_rig_names({"ring": ("rig", section)}, tmp_path)  # nothing made yet: accepted
    save_rig(rig_from_config(section), tmp_path / "ring.json")
    wc.check_rig_names({"ring": ("rig", section)}, tmp_path)  # the same rig: accepted
    with pytest.raises(VoxposeError, match="config key rig: the rig named 'ring' differs"):
        wc.check_rig_names({"ring": ("rig", section | {"n_cameras": 8})}, tmp_path)
    wc.check_rig_names({"ring8": ("rig", section | {"n_cameras": 8, "name": "ring8"})}, tmp_path)  # renamed


def test_a_rig_derived_from_the_default_rig_is_tagged_by_both_names():
    rig = {"name": "main", "file": None, "n_cameras": 6, "radius": 4.0}
    claims = {"rigs": [{"name": "four", "n_cameras": 4}, {"name": "lab", "file": "lab.json"}], "retrain": ["four"]}
    rigs = wc.claims_rigs(claims, rig)
    assert set(rigs) == {"main.four", "lab"}
    assert rigs["main.four"]["name"] == "four" and rigs["main.four"]["n_cameras"] == 4
    assert set(wc.claims_rigs(claims, rig | {"name": "other"})) == {"other.four", "lab"}


@pytest.mark.parametrize("method", ["mppca", "kmeans"])
def test_a_fit_reads_only_its_methods_feature_keys(config, method):
    """The fit rule's parameters are ``feature_params``: a fit given only them equals the fit given the whole
    section (so no key it reads is left out), and the other method's keys are not among them (so changing one
    of those reruns nothing of this method)."""
    from voxpose.features.model import FeatureModel

    rows = np.random.default_rng(0).gamma(2.0, size=(300, 12))
    cfg = dict(config["features"], n_components=8, n_latent=2, max_iter=20, fit_subsample=None)
    params = wc.feature_params(method, cfg)
    whole, own = (FeatureModel.fit_rows(method, rows, len(rows), c, 3) for c in (cfg, params))
    frames = [rows[:50], rows[50:120]]
    for a, b in zip(own.transform_frames(frames), whole.transform_frames(frames), strict=True):
        np.testing.assert_array_equal(a, b)
    other = {"mppca": {"kmeans_neighbours"}, "kmeans": {"n_latent", "tol"}}[method]
    assert other <= cfg.keys() and not other & params.keys()
    assert wc.feature_params(method, dict(cfg, **{k: 9 for k in other})) == params
