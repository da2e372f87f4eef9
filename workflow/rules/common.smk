# Helpers shared by all rules: config validation, the motion list, experiments, parameter-set tags.
# All logic lives in voxpose.workflow_config (tested); this file only binds it to the workflow.

import json
import math
import os
import shlex
import sys

from voxpose import workflow_config as wc
from voxpose.cli.main import SUBCOMMANDS
from voxpose.config_schema import load_yaml
from voxpose.errors import VoxposeError
from voxpose.import_graph import code_hash
from voxpose.io.bvh import read_duration
from voxpose.provenance import config_hash


def _fail(err):
    # a user mistake in the config: one line, non-zero exit, before any job runs
    print(f"voxpose: error: {err}", file=sys.stderr)
    sys.exit(2)


def _note(message):
    # something left out of the run on purpose: one line
    print(f"voxpose: {message}", file=sys.stderr)


try:
    wc.validate_config(config)
    if config["bvh_dir"]:
        SOURCE_BVH = wc.bvh_dir_motions(config["bvh_dir"])
        # every header is read here, as `voxpose motion` reads it: a bad file is one line naming it, before any
        # job (read lazily while Snakemake sized the jobs, it was a traceback blaming some rule)
        DURATIONS = {name: read_duration(path) for name, path in SOURCE_BVH.items()}
        DERIVED, absent = wc.derived_motions(config.get("derived", []), SOURCE_BVH)
        if absent:
            _note(f"derived: skipped {len(absent)} of {len(absent) + len(DERIVED)} derived motions whose source is "
                  f"not in bvh_dir: {', '.join(absent)}")  # fmt: skip
        GENERATED = {}
        EXPERIMENT_CFG, EXPERIMENT_KEY = config["bvh_experiments"], "bvh_experiments"
        GENERALISATION_KEY = "bvh_generalisation"
    else:
        SOURCE_BVH, DERIVED, DURATIONS = {}, {}, {}
        GENERATED = wc.generated_motions(config["generated"])
        EXPERIMENT_CFG, EXPERIMENT_KEY = config["experiments"], "experiments"
        GENERALISATION_KEY = "generalisation"
    MOTIONS = sorted([*SOURCE_BVH, *DERIVED, *GENERATED])
    SHIPPED = load_yaml(workflow.source_path("../../config/config.yaml"))
    EXPERIMENTS, SKIPPED = wc.resolve_experiments(EXPERIMENT_CFG, MOTIONS, EXPERIMENT_KEY, SHIPPED[EXPERIMENT_KEY])
    for name in SKIPPED:
        _note(f"{EXPERIMENT_KEY}.{name}: skipped, no training or no test motion among the {len(MOTIONS)} motions "
              f"(the shipped experiment names the shared data's motions; define your own in {EXPERIMENT_KEY})")  # fmt: skip
    HELD_OUT, GROUPS_SKIPPED = wc.resolve_generalisation(
        config[GENERALISATION_KEY], MOTIONS, GENERALISATION_KEY, {m: d[1] for m, d in DERIVED.items()},
        SHIPPED[GENERALISATION_KEY],
    )
    if GROUPS_SKIPPED:
        _note(f"{GENERALISATION_KEY}: skipped {len(GROUPS_SKIPPED)} groups with no motion or no training motion "
              f"left among the {len(MOTIONS)} motions: {', '.join(GROUPS_SKIPPED)}")  # fmt: skip
    CLAIM_RIGS = wc.claims_rigs(config["claims"], config["rig"])
    DEGRADED = wc.degraded_sets(config["claims"], config["rig"]["name"], wc.rig_camera_count(config["rig"]))
    wc.check_rig_names(
        {config["rig"]["name"]: ("rig", config["rig"])} | {t: ("claims.rigs", s) for t, s in CLAIM_RIGS.items()},
        "results/rigs",
    )
    if config["claims"]["experiment"] not in EXPERIMENT_CFG:
        raise VoxposeError(f"config key claims.experiment: no experiment named {config['claims']['experiment']!r}")
except VoxposeError as err:
    _fail(err)

# The config of this run, recorded beside every table it makes (voxpose.provenance): the table commands read it from
# the environment, not from a param, so that a table is remade when its inputs change, not whenever any config key
# does; `envvars` passes it on to cluster jobs.
os.environ["VOXPOSE_CONFIG_HASH"] = config_hash(config)


envvars:
    "VOXPOSE_CONFIG_HASH",

def held_out(group):
    """The internal experiment that holds out generalisation group ``group`` (a name no config experiment has)."""
    return f"held_out.{group}"


# Fits are cached by content: an experiment's features and regressor live under the tag of its training motions
# (wc.motion_set_tag), so experiments with the same training set share them; each test set is evaluated under the
# tag of its own motions. SETS: tag -> motions; TRAIN: experiment -> training tag; TESTS: experiment -> {set: tag}.
# Each held-out group of the generalisation section is an experiment like the others (RUNS): it trains on the
# rest of the pool and tests on the group.
RUNS = EXPERIMENTS | {held_out(group): e for group, e in HELD_OUT.items()}
TRAIN = {exp: wc.motion_set_tag(e["train"]) for exp, e in RUNS.items()}
TESTS = {exp: {s: wc.motion_set_tag(m) for s, m in e["test_sets"].items()} for exp, e in RUNS.items()}
# a left-out experiment's paths name the empty set, so that the rules wired to it still parse; final_targets()
# leaves its artifacts out, so nothing asks for them
TRAIN |= {exp: wc.motion_set_tag([]) for exp in SKIPPED}
TESTS |= {exp: {"test": wc.motion_set_tag([])} for exp in SKIPPED}
SETS = {wc.motion_set_tag(m): m for e in RUNS.values() for m in (e["train"], *e["test_sets"].values())}

RIG = config["rig"]["name"]
RIG_SECTIONS = {RIG: config["rig"], **CLAIM_RIGS}
DESC_CFG = config["descriptor"]
DESC = wc.descriptor_tag(DESC_CFG)
FEAT_CFG = config["features"]


def sweep_descriptors():
    """Descriptor parameter sets of the Figure 4 sweeps (Section 6), each varying one setting."""
    sets = [dict(DESC_CFG, r_max=r) for r in config["figure4"]["r_max"]]
    sets += [dict(DESC_CFG, n_r=n) for n in config["figure4"]["n_r"]]
    sets += [dict(DESC_CFG, n_e=ne, n_a=na) for ne, na in config["figure4"]["ne_na"]]
    return sets


DESCRIPTORS = {wc.descriptor_tag(c): c for c in [DESC_CFG, *sweep_descriptors()]}


def feature_sets():
    """Feature parameter sets by tag: the main MPPCA and K-means ones and the Figure 4 K sweep."""
    cfgs = [("mppca", FEAT_CFG), ("kmeans", FEAT_CFG)]
    cfgs += [("mppca", dict(FEAT_CFG, n_components=k)) for k in config["figure4"]["n_components"]]
    return {wc.feature_tag(method, cfg): (method, wc.feature_params(method, cfg)) for method, cfg in cfgs}


FEATURES = feature_sets()
MPPCA = wc.feature_tag("mppca", FEAT_CFG)
KMEANS = wc.feature_tag("kmeans", FEAT_CFG)

# The measured claims (workflow/rules/claims.smk): 2D shape contexts and A&T codebooks live beside the 3D ones
# (desc and feat wildcards) and degraded voxel sets beside the rigs' (rig wildcard, names with "__").
CLAIMS = config["claims"]
CLAIMS_EXP = CLAIMS["experiment"]
CTX = wc.contour_tag(CLAIMS["contour"])
AT_ONE = wc.at_tag(CLAIMS["at"], CLAIMS["at"]["camera"])
AT_ALL = wc.at_tag(CLAIMS["at"], "all")
NOT_DEGRADED = r"(?:(?!__)[A-Za-z0-9_.-])+"
NOT_CONTOURS = r"(?!sc2d-)[^/]+"


wildcard_constraints:
    motion=r"[^/]+",
    rig=r"[A-Za-z0-9_.-]+",
    desc=r"[^/]+",
    feat=r"[^/]+",
    exp=r"[A-Za-z0-9_]+",
    train=r"n\d+-[0-9a-f]+",
    set=r"n\d+-[0-9a-f]+",


# Resources (issue 9). Every rule sets threads, mem_mb (MB) and runtime (minutes) with one of the two helpers below,
# as `(base + slope * size) * attempt`: `base` covers the interpreter and fixed-size state, `slope` the part that grows
# with the data; `attempt` doubles the request when a cluster job killed for memory or time is retried (profile
# `retries`). Both numbers come from benchmarks/rule_resources.py (peak RSS and wall time per job against input size),
# with headroom; profiles/README.md records the measurements. Rules in the `per_motion` group use by_frames, because
# a batch is submitted before its members' inputs exist; every other rule uses by_input.
#
# Threads: every rule asks for 1. A rule's `threads` also sets its BLAS/OpenMP threads (voxpose.cli.main), and on the
# 2-core machine BLAS threads did not pay for these matrix sizes (default run's inputs, wall time of one job at 1 and
# at 2 threads): fit-features 28.8 s at 1 thread, 39 s at 2; features 10.5 and 9.5 s; silhouette-features 8.7 and
# 16.3 s. Two 1-thread jobs side by side use both cores; a 2-thread job blocked the second core for little gain.


def motion_frames(motion):
    """Frames a motion has once loaded (resampled to motions.fps), known before any of its jobs run: from the
    config for generated motions, from the BVH header otherwise (a derived motion has its source's duration)."""
    if motion in GENERATED:
        return GENERATED[motion][2]
    n_frames, frame_time = DURATIONS[DERIVED[motion][1] if motion in DERIVED else motion]
    return math.ceil(n_frames * frame_time * wc.motion_settings(motion, config["motions"])["fps"])


def by_frames(base, per_frame):
    """``(base + per_frame * frames of the job's motion) * attempt``, for the per-motion rules."""
    return lambda wildcards, attempt: math.ceil((base + per_frame * motion_frames(wildcards.motion)) * attempt)


def by_input(base, per_input_mb=0):
    """``(base + per_input_mb * total input MB) * attempt``, for rules whose inputs exist when they are submitted."""
    return lambda wildcards, input, attempt: math.ceil((base + per_input_mb * input.size_mb) * attempt)


def code(subcommand):
    """Content hash of the import closure of the module that defines ``voxpose <subcommand>``, the command the
    rule runs (Snakemake does not see edits to the installed package); editing any module the command reaches,
    directly or not, reruns the rule and its dependants, and nothing else (voxpose.import_graph)."""
    return code_hash(SUBCOMMANDS[subcommand].module)


def arg(value):
    """A Python value as one shell-quoted JSON argument, keys sorted: a `--configfile` merge reorders keys, and a
    reordered string would look like a changed parameter to Snakemake."""
    return shlex.quote(json.dumps(value, sort_keys=True))


def run_dir(exp, desc, feat, rig=None):
    """Where the regressor of experiment ``exp`` (its training set's tag) lives."""
    return f"results/runs/{TRAIN[exp]}/{rig or RIG}/{desc}/{feat}"


def test_dir(exp, desc, feat, test=None, rig=None):
    """Where experiment ``exp``'s regressor is evaluated on its test set ``test`` (default: the first one)."""
    return f"{run_dir(exp, desc, feat, rig)}/sets/{TESTS[exp][test or next(iter(TESTS[exp]))]}"


def figure4_runs():
    """(label, value, run directory) of every Figure 4 point: each its own cached target."""
    f4 = config["figure4"]
    runs = []
    for r in f4["r_max"]:
        runs.append(("r_max", r, test_dir("figure4", wc.descriptor_tag(dict(DESC_CFG, r_max=r)), MPPCA)))
    for n in f4["n_r"]:
        runs.append(("n_r", n, test_dir("figure4", wc.descriptor_tag(dict(DESC_CFG, n_r=n)), MPPCA)))
    for ne, na in f4["ne_na"]:
        tag = wc.descriptor_tag(dict(DESC_CFG, n_e=ne, n_a=na))
        runs.append(("ne_na", f"{ne}x{na}", test_dir("figure4", tag, MPPCA)))
    for k in f4["n_components"]:
        feat = wc.feature_tag("mppca", dict(FEAT_CFG, n_components=k))
        runs.append(("n_components", k, test_dir("figure4", DESC, feat)))
    return runs


def bvh_path(w):
    if w.motion in SOURCE_BVH:
        return SOURCE_BVH[w.motion]
    if w.motion in DERIVED:
        return f"results/bvh/derived/{w.motion}.bvh"
    return f"results/bvh/generated/{w.motion}.bvh"


def set_descriptors(tag):
    """Input function: the descriptor files of the motions of set ``tag`` (a wildcard's name)."""
    return lambda w: expand(
        "results/descriptors/{rig}/{desc}/{motion}.h5", rig=w.rig, desc=w.desc, motion=SETS[getattr(w, tag)]
    )


def set_motions(tag):
    """Input function: the motion files of the motions of set ``tag`` (a wildcard's name)."""
    return lambda w: expand("results/motions/{motion}.h5", motion=SETS[getattr(w, tag)])


def run_file(exp, feat, name, desc=None, test=None):
    """A file of experiment ``exp``'s evaluation on test set ``test`` (default: its first)."""
    return f"{test_dir(exp, desc or DESC, feat, test)}/{name}"


def data_set():
    """What the motions are, as the report names the data set beside every verdict."""
    folders = config["bvh_dir"]
    if not folders:
        return "generated motions (voxpose's embedded default set)"
    return "motion capture in " + ", ".join(folders if isinstance(folders, list) else [folders])


def bootstrap_args():
    """The seeded bootstrap options of the tables with intervals."""
    return f"--bootstrap {config['report']['bootstrap']} --seed {config['seed']}"


def final_targets():
    """Every motion's poses, and the artifacts whose experiments are in the run (a shipped experiment with no
    motions in bvh_dir is left out, and so are its tables and figures)."""
    model = lambda exp: f"results/models/{exp}/{RIG}/{DESC}/{MPPCA}/model.h5"  # noqa: E731
    needs = [  # (experiments, the artifacts made from them)
        (["table1"], ["results/tables/table1.csv", "results/tables/table1.md", "results/tables/table1.html",
                      model("table1")]),  # fmt: skip
        (["table1", "table2"], ["results/tables/claims.csv", "results/tables/claims.html"]),
        (["table1", "table2", "figure4"], ["results/report/summary.html"]),
        (["table2"], ["results/tables/table2.csv", "results/tables/table2.md", "results/tables/table2.html", model("table2"),
                      "results/figures/gallery.png"]),  # fmt: skip
        (["table1", "table2"], ["results/figures/joint_errors.png", "results/figures/error_over_time.png"]),
        (["figure4"], ["results/figures/figure4.png", "results/figures/figure4.pdf", "results/tables/figure4.csv",
                      "results/tables/figure4.html"]),  # fmt: skip
        ([CLAIMS_EXP], ["results/figures/camera_rigs.png", "results/tables/camera_rigs.csv",
                        "results/tables/camera_rigs.html", "results/figures/robustness.png",
                        "results/tables/robustness.csv", "results/tables/robustness.html"]),  # fmt: skip
    ]
    artifacts = [path for exps, paths in needs if set(exps) <= set(EXPERIMENTS) for path in paths]
    artifacts += [f"results/tables/experiments/{exp}.csv" for exp in EXPERIMENTS]
    if HELD_OUT:
        artifacts += ["results/tables/generalisation.csv", "results/tables/generalisation.html",
                      "results/figures/generalisation.png"]
    return artifacts + [f"results/motions/{motion}.h5" for motion in MOTIONS]


def run_pair(exp, feat, desc=None):
    """A run's summary.json and predictions.h5, as the tables' ``--<run> SUMMARY PREDICTIONS`` take them."""
    return [run_file(exp, feat, "summary.json", desc=desc), run_file(exp, feat, "predictions.h5", desc=desc)]
