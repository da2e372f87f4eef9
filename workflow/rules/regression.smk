# Pose PCA (Eq. 1), the multivariate RVM (Section 3) and the baselines fitted once per training set; each test
# set evaluated on its own: predictions and Eq. 6 errors per frame.


rule regress:  # lint: no conda/container, see Snakefile
    input:
        features="results/features/{train}/{rig}/{desc}/{feat}/sets/{train}.h5",
        motions=set_motions("train"),
    output:
        regressor="results/runs/{train}/{rig}/{desc}/{feat}/regressor.h5",
        baselines="results/runs/{train}/{rig}/{desc}/{feat}/baselines.h5",
        fit="results/runs/{train}/{rig}/{desc}/{feat}/fit.json",
    params:
        train=lambda w: ",".join(SETS[w.train]),
        cfg=arg(config["regression"]),
        seed=config["seed"],
        code=code("regress"),
    log:
        "results/logs/regress/{train}/{rig}/{desc}/{feat}.log",
    threads: 1  # the MVRVM's moves are sequential; two experiments fit side by side instead
    resources:
        mem_mb=by_input(1000, 50),
        runtime=by_input(30, 5),
    shell:
        "voxpose regress {input.features} --train {params.train} --params {params.cfg} --seed {params.seed}"
        " --regressor {output.regressor} --baselines {output.baselines} --fit {output.fit} --log {log}"
        " --threads {threads} {input.motions}"


rule evaluate:  # lint: no conda/container, see Snakefile
    input:
        features="results/features/{train}/{rig}/{desc}/{feat}/sets/{set}.h5",
        regressor="results/runs/{train}/{rig}/{desc}/{feat}/regressor.h5",
        baselines="results/runs/{train}/{rig}/{desc}/{feat}/baselines.h5",
        fit="results/runs/{train}/{rig}/{desc}/{feat}/fit.json",
        motions=set_motions("set"),
    output:
        summary="results/runs/{train}/{rig}/{desc}/{feat}/sets/{set}/summary.json",
        predictions="results/runs/{train}/{rig}/{desc}/{feat}/sets/{set}/predictions.h5",
        angles="results/runs/{train}/{rig}/{desc}/{feat}/sets/{set}/predicted_angles.csv",
    params:
        test=lambda w: ",".join(SETS[w.set]),
        cfg=arg(config["regression"]),
        code=code("evaluate"),
    log:
        "results/logs/evaluate/{train}/{rig}/{desc}/{feat}/{set}.log",
    threads: 1
    resources:
        mem_mb=by_input(300, 3),  # profiles/README.md
        runtime=by_input(5, 1),
    shell:
        "voxpose evaluate {input.features} --regressor {input.regressor} --baselines {input.baselines}"
        " --fit {input.fit} --test {params.test} --params {params.cfg} --predictions {output.predictions}"
        " --angles {output.angles} -o {output.summary} --log {log} {input.motions}"
