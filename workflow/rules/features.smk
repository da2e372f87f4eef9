# Feature transformation (Section 5): MPPCA fitted on a training set's descriptors -> Eq. 5 features of every
# motion set the fit is used on; the K-means soft-vote histogram as the baseline (Table 1, third row).
# {train} and {set} are motion-set tags (common.smk): experiments with the same training motions share one fit.


rule fit_features:  # lint: no conda/container, see Snakefile
    input:
        descriptors=set_descriptors("train"),
        motions=set_motions("train"),  # true headings: training frames turned to face forwards (heading_sense)
    output:
        "results/features/{train}/{rig}/{desc}/{feat}/model.h5",
    wildcard_constraints:
        desc=NOT_CONTOURS,
    params:
        method=lambda w: FEATURES[w.feat][0],
        cfg=lambda w: arg(FEATURES[w.feat][1]),
        seed=config["seed"],
        code=code("fit-features"),
    log:
        "results/logs/fit_features/{train}/{rig}/{desc}/{feat}.log",
    threads: 1  # BLAS threads do not pay here (common.smk, "Threads")
    resources:
        mem_mb=by_input(700, 0.2),  # one descriptor file at a time (profiles/README.md)
        runtime=by_input(60, 0.2),
    shell:
        "voxpose fit-features --method {params.method} --params {params.cfg} --seed {params.seed}"
        " --motions {input.motions} -o {output} --log {log} --threads {threads} {input.descriptors}"


rule features:  # lint: no conda/container, see Snakefile
    input:
        model="results/features/{train}/{rig}/{desc}/{feat}/model.h5",
        descriptors=set_descriptors("set"),
    output:
        "results/features/{train}/{rig}/{desc}/{feat}/sets/{set}.h5",
    wildcard_constraints:
        desc=NOT_CONTOURS,
    params:
        code=code("features"),
    log:
        "results/logs/features/{train}/{rig}/{desc}/{feat}/{set}.log",
    threads: 1  # BLAS threads do not pay here (common.smk, "Threads")
    resources:
        mem_mb=by_input(550, 0.3),  # profiles/README.md
        runtime=by_input(10, 0.1),
    shell:
        "voxpose features {input.model} -o {output} --log {log} --threads {threads} {input.descriptors}"
