# Pose PCA (Eq. 1) and the multivariate RVM (Section 3) per experiment; predictions and Eq. 6 errors per frame.


rule regress:
    input:
        features="results/features/{exp}/{rig}/{desc}/{feat}/features.h5",
        motions=lambda w: expand("results/motions/{motion}.h5", motion=experiment_motions(w.exp)),
    output:
        model="results/runs/{exp}/{rig}/{desc}/{feat}/regressor.h5",
        predictions="results/runs/{exp}/{rig}/{desc}/{feat}/predictions.h5",
        angles="results/runs/{exp}/{rig}/{desc}/{feat}/predicted_angles.csv",
        summary="results/runs/{exp}/{rig}/{desc}/{feat}/summary.json",
    params:
        train=lambda w: ",".join(EXPERIMENTS[w.exp]["train"]),
        test=lambda w: ",".join(EXPERIMENTS[w.exp]["test"]),
        cfg=arg(config["regression"]),
        seed=config["seed"],
        code=code("regress"),
    log:
        "results/logs/regress/{exp}/{rig}/{desc}/{feat}.log",
    threads: 1  # the MVRVM's moves are sequential; two experiments fit side by side instead
    resources:
        mem_mb=by_input(1000, 50),
        runtime=by_input(30, 5),
    shell:
        "voxpose regress {input.features} --train {params.train} --test {params.test}"
        " --params {params.cfg} --seed {params.seed} --model {output.model} --predictions {output.predictions}"
        " --angles {output.angles} --summary {output.summary} --log {log} --threads {threads}"
        " {input.motions}"
