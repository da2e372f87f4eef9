# Trained pipelines as model files for `voxpose predict` on new data: carving settings, descriptor parameters,
# feature model, pose PCA, MVRVM and output skeleton in one versioned HDF5 file (voxpose/apply/model_file.py).


rule export_model:  # lint: no conda/container, see Snakefile
    input:
        feature_model=lambda w: f"results/features/{TRAIN[w.exp]}/{w.rig}/{w.desc}/{w.feat}/model.h5",
        regressor=lambda w: f"{run_dir(w.exp, w.desc, w.feat, w.rig)}/regressor.h5",
        summary=lambda w: f"{test_dir(w.exp, w.desc, w.feat, rig=w.rig)}/summary.json",  # provenance: test errors
        motions=lambda w: expand("results/motions/{motion}.h5", motion=EXPERIMENTS[w.exp]["train"]),
    output:
        "results/models/{exp}/{rig}/{desc}/{feat}/model.h5",
    params:
        voxels=arg(config["voxels"]),
        descriptor=lambda w: arg(DESCRIPTORS[w.desc]),
        regression=arg(config["regression"]),
        seed=config["seed"],
        name=lambda w: f"{w.exp}/{w.rig}/{w.desc}/{w.feat}",
        code=code("export-model"),
    log:
        "results/logs/export_model/{exp}/{rig}/{desc}/{feat}.log",
    threads: 1
    resources:  # measured: 104 MB, 1.2-1.3 s CPU on 0.7-0.9 MB
        mem_mb=by_input(300, 20),
        runtime=by_input(5, 1),
    shell:
        "voxpose export-model --feature-model {input.feature_model} --regressor {input.regressor}"
        " --summary {input.summary} --motions {input.motions} --voxels {params.voxels}"
        " --descriptor {params.descriptor} --regression {params.regression} --seed {params.seed}"
        " --name {params.name} -o {output} --log {log}"
