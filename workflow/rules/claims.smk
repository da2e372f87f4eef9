# The paper's claims, measured (issue 8): one regressor for any camera setup, robustness to degraded silhouettes,
# and the Agarwal & Triggs baseline computed instead of quoted. Cheap by design: the claims experiment (Figure 4's
# split by default) trains the regressors; test rigs and degradations carve only its test motions.

import re


# --- Agarwal & Triggs-style features: 2D shape contexts per view, a K-means soft histogram per view ---


rule silhouette_contexts:  # lint: no conda/container, see Snakefile
    input:
        motion="results/motions/{motion}.h5",
        rig="results/rigs/{rig}.json",
    output:
        "results/claims/contexts/{rig}/{ctx}/{motion}.h5",
    params:
        cfg=arg(CLAIMS["contour"]),
        voxels=arg(config["voxels"]),
        seed=config["seed"],
        code=code("silhouette-contexts"),
    log:
        "results/logs/silhouette_contexts/{rig}/{ctx}/{motion}.log",
    group: "per_motion"  # batched into one cluster job per few motions (profiles/slurm)
    threads: 1
    resources:
        mem_mb=by_frames(300, 0.8),  # profiles/README.md; 2D shape contexts ~60 ms per frame of 6 views
        runtime=by_frames(5, 0.005),
    shell:
        "voxpose silhouette-contexts {input.motion} --rig {input.rig} --params {params.cfg}"
        " --voxel-params {params.voxels} --seed {params.seed} -o {output} --log {log}"


rule fit_silhouette_features:  # lint: no conda/container, see Snakefile
    input:
        set_contexts("train"),
    output:
        "results/features/{train}/{rig}/{desc}/{feat}/model.h5",
    wildcard_constraints:
        desc=re.escape(CTX),
        feat=f"{re.escape(AT_ONE)}|{re.escape(AT_ALL)}",
    params:
        cfg=arg(CLAIMS["at"]),
        cameras=at_cameras,
        seed=config["seed"],
        code=code("fit-silhouette-features"),
    log:
        "results/logs/fit_silhouette_features/{train}/{rig}/{desc}/{feat}.log",
    threads: 1  # BLAS threads do not pay here (common.smk, "Threads")
    resources:  # measured: 111-143 MB, 1.1-1.4 s CPU on 11-22 MB
        mem_mb=by_input(300, 0.1),  # one motion's contexts at a time (profiles/README.md)
        runtime=by_input(5, 0.02),
    shell:
        "voxpose fit-silhouette-features --params {params.cfg} --cameras {params.cameras} --seed {params.seed}"
        " -o {output} --log {log} --threads {threads} {input}"


rule silhouette_features:  # lint: no conda/container, see Snakefile
    input:
        model="results/features/{train}/{rig}/{desc}/{feat}/model.h5",
        contexts=set_contexts("set"),
    output:
        "results/features/{train}/{rig}/{desc}/{feat}/sets/{set}.h5",
    wildcard_constraints:
        desc=re.escape(CTX),
        feat=f"{re.escape(AT_ONE)}|{re.escape(AT_ALL)}",
    params:
        code=code("silhouette-features"),
    log:
        "results/logs/silhouette_features/{train}/{rig}/{desc}/{feat}/{set}.log",
    threads: 1  # BLAS threads do not pay here (common.smk, "Threads")
    resources:  # measured: 97-103 MB (flat), 0.9-1.5 s CPU on 6-22 MB
        mem_mb=by_input(300, 0.1),  # profiles/README.md
        runtime=by_input(5, 0.02),
    shell:
        "voxpose silhouette-features {input.model} {input.contexts} -o {output} --log {log} --threads {threads}"


# --- robustness: degraded silhouettes carved from the default rig (voxel sets named {rig}__{kind}{level}__min{k}) ---


rule voxelize_degraded:  # lint: no conda/container, see Snakefile
    input:
        motion="results/motions/{motion}.h5",
        rig=f"results/rigs/{RIG}.json",
    output:
        "results/voxels/{voxel_set}/{motion}.h5",
    wildcard_constraints:
        voxel_set="|".join(map(re.escape, DEGRADED)) or "^$",
    params:
        degradation=lambda w: arg(DEGRADED[w.voxel_set]),
        cfg=arg(config["voxels"]),
        seed=config["seed"],
        code=code("voxelize-degraded"),
    log:
        "results/logs/voxelize_degraded/{voxel_set}/{motion}.log",
    group: "per_motion"  # batched into one cluster job per few motions (profiles/slurm)
    threads: 1
    resources:
        mem_mb=by_frames(300, 0.4),  # as voxelize; carving a degraded set costs up to 4x (bench_claims.py)
        runtime=by_frames(5, 0.02),
    shell:
        "voxpose voxelize-degraded {input.motion} --rig {input.rig} --params {params.cfg}"
        " --degradation {params.degradation} --seed {params.seed} -o {output} --log {log}"


# --- one regressor, trained on the default rig, tested on other rigs and degraded sets without retraining ---


rule transfer_features:  # lint: no conda/container, see Snakefile
    input:
        model="results/features/{train}/{rig}/{desc}/{feat}/model.h5",
        descriptors=lambda w: expand(
            "results/descriptors/{vs}/{desc}/{motion}.h5", vs=w.voxel_set, desc=w.desc, motion=claims_test(w.voxel_set)
        ),
    output:
        f"{TRANSFER}/features.h5",
    wildcard_constraints:
        voxel_set=r"[^/]+",
        desc=NOT_CONTOURS,
    params:
        code=code("features"),
    log:
        "results/logs/transfer_features/{voxel_set}/{train}/{rig}/{desc}/{feat}.log",
    threads: 1
    resources:  # measured: 95 MB (flat), 0.9 s CPU on 2 MB
        mem_mb=by_input(450, 1),  # profiles/README.md
        runtime=by_input(5, 0.05),
    shell:
        "voxpose features {input.model} -o {output} --log {log} --threads {threads} {input.descriptors}"


rule transfer_silhouette_features:  # lint: no conda/container, see Snakefile
    input:
        model="results/features/{train}/{rig}/{desc}/{feat}/model.h5",
        contexts=lambda w: expand(
            "results/claims/contexts/{vs}/{desc}/{motion}.h5", vs=w.voxel_set, desc=w.desc, motion=claims_test(w.voxel_set)
        ),
    output:
        f"{TRANSFER}/features.h5",
    wildcard_constraints:
        voxel_set=r"[^/]+",
        desc=r"sc2d-[^/]+",
    params:
        code=code("silhouette-features"),
    log:
        "results/logs/transfer_features/{voxel_set}/{train}/{rig}/{desc}/{feat}.log",
    threads: 1
    resources:  # measured: 102 MB, 1.0 s CPU on 6 MB
        mem_mb=by_input(300, 1),
        runtime=by_input(5, 0.02),
    shell:
        "voxpose silhouette-features {input.model} {input.contexts} -o {output} --log {log}"


rule transfer_predict:  # lint: no conda/container, see Snakefile
    input:
        features=f"{TRANSFER}/features.h5",
        regressor="results/runs/{train}/{rig}/{desc}/{feat}/regressor.h5",
        motions=lambda w: expand("results/motions/{motion}.h5", motion=claims_test(w.voxel_set)),
    output:
        f"{TRANSFER}/summary.json",
    wildcard_constraints:
        voxel_set=r"[^/]+",
    params:
        test=lambda w: ",".join(claims_test(w.voxel_set)),
        cfg=arg(config["regression"]),
        code=code("evaluate"),
    log:
        "results/logs/transfer_predict/{voxel_set}/{train}/{rig}/{desc}/{feat}.log",
    threads: 1
    resources:  # measured: 101 MB, 1.1 s CPU on 0.1 MB (as evaluate)
        mem_mb=by_input(300, 20),
        runtime=by_input(5, 1),
    shell:
        "voxpose evaluate {input.features} {input.motions} --regressor {input.regressor} --test {params.test}"
        " --params {params.cfg} -o {output} --log {log}"


# --- the two figures ---


rule camera_figure:  # lint: no conda/container, see Snakefile
    input:
        [r["summary"] for r in camera_runs() if r["summary"]],
    output:
        png=report("results/figures/camera_rigs.png", caption="../report/camera_rigs.rst", category="Claims"),
        csv=report("results/tables/camera_rigs.csv", caption="../report/camera_rigs_table.rst", category="Claims"),
        meta=report("results/tables/camera_rigs.meta.json", caption="../report/provenance.rst",
                    category="Provenance"),  # fmt: skip
        html=report("results/tables/camera_rigs.html", caption="../report/camera_rigs_table.rst", category="Claims"),
    params:
        runs=arg(camera_runs()),
        code=code("camera-figure"),
    log:
        "results/logs/camera_figure.log",
    localrule: True
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    shell:
        "voxpose camera-figure --runs {params.runs} --png {output.png} --csv {output.csv}"
        " --html {output.html} --log {log}"


rule robustness_figure:  # lint: no conda/container, see Snakefile
    input:
        [r["summary"] for r in robustness_runs()],
    output:
        png=report("results/figures/robustness.png", caption="../report/robustness.rst", category="Claims"),
        csv=report("results/tables/robustness.csv", caption="../report/robustness_table.rst", category="Claims"),
        meta=report("results/tables/robustness.meta.json", caption="../report/provenance.rst",
                    category="Provenance"),  # fmt: skip
        html=report("results/tables/robustness.html", caption="../report/robustness_table.rst", category="Claims"),
    params:
        runs=arg(robustness_runs()),
        code=code("robustness-figure"),
    log:
        "results/logs/robustness_figure.log",
    localrule: True
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    shell:
        "voxpose robustness-figure --runs {params.runs} --png {output.png} --csv {output.csv}"
        " --html {output.html} --log {log}"
