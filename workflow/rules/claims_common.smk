# Helpers of the measured claims' rules (claims.smk): which motions each voxel set tests, where each transfer's
# summary lives, and the two figures' run lists. Apart from the rules, as Snakemake's linter asks.


def claims_test(voxel_set):
    """Test motions evaluated on a rig or degraded voxel set (degradations: the first robustness_motions)."""
    test = EXPERIMENTS[CLAIMS_EXP]["test"]
    return test[: CLAIMS["robustness_motions"]] if voxel_set in DEGRADED else test


def transfer_summary(voxel_set, method="mppca"):
    """Summary of the regressor trained on the claims experiment at the default rig, tested on ``voxel_set``.

    The path names everything the result depends on (test set, experiment, training rig, descriptor and feature
    tags), so a changed setting writes new files instead of overwriting these, and changing it back finds them.
    """
    desc, feat = (DESC, MPPCA) if method == "mppca" else (CTX, AT_ALL)
    return f"results/claims/transfer/{voxel_set}/{TRAIN[CLAIMS_EXP]}/{RIG}/{desc}/{feat}/summary.json"


TRANSFER = "results/claims/transfer/{voxel_set}/{train}/{rig}/{desc}/{feat}"


def at_cameras(w):
    return arg("all" if w.feat == AT_ALL else [CLAIMS["at"]["camera"]])


def set_contexts(tag):
    """Input function: the 2D shape-context files of the motions of set ``tag`` (a wildcard's name)."""
    return lambda w: expand(
        "results/claims/contexts/{rig}/{ctx}/{motion}.h5", rig=w.rig, ctx=w.desc, motion=SETS[getattr(w, tag)]
    )


def camera_runs():
    """Camera-figure entries: transferred (every rig), retrained (default and claims.retrain), A&T (same count)."""
    n_default = wc.rig_camera_count(config["rig"])
    runs = []
    for tag, section in RIG_SECTIONS.items():
        name, n = section["name"], wc.rig_camera_count(section)
        runs.append({"rig": name, "cameras": n, "series": f"trained on {RIG}, not retrained (voxels)",
                     "summary": transfer_summary(tag)})  # fmt: skip
        if tag == RIG or name in CLAIMS["retrain"]:
            runs.append({"rig": name, "cameras": n, "series": "retrained on this rig (voxels)",
                         "summary": f"{test_dir(CLAIMS_EXP, DESC, MPPCA, rig=tag)}/summary.json"})  # fmt: skip
        runs.append({"rig": name, "cameras": n, "series": f"A&T, {n_default} views concatenated, trained on {RIG}",
                     "summary": transfer_summary(tag, "at") if n == n_default else None})  # fmt: skip
    return runs


def robustness_runs():
    runs = []
    for name, spec in DEGRADED.items():
        kinds = [k for k, levels in CLAIMS["degradations"].items() if levels] if spec["kind"] == "none" else [spec["kind"]]
        for kind in kinds:  # the clean set is level 0 of every kind
            runs.append({"kind": kind, "level": spec["level"], "carving": f"inside >= {spec['min_views']} views",
                         "summary": transfer_summary(name)})  # fmt: skip
    return runs
