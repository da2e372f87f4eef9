# Body model -> silhouettes from the calibrated rig -> carved voxels, surface and basis voxels (Sections 4, 6).


rule rig:  # lint: no conda/container, see Snakefile
    input:
        lambda w: [RIG_SECTIONS[w.rig]["file"]] if RIG_SECTIONS[w.rig]["file"] else [],
    output:
        "results/rigs/{rig}.json",
    params:
        cfg=lambda w: arg(RIG_SECTIONS[w.rig]),
        code=code("rig"),
    log:
        "results/logs/rig/{rig}.log",
    localrule: True
    threads: 1
    resources:
        mem_mb=200,
        runtime=2,
    shell:
        "voxpose rig --params {params.cfg} -o {output} --log {log}"


rule voxelize:  # lint: no conda/container, see Snakefile
    input:
        motion="results/motions/{motion}.h5",
        rig="results/rigs/{rig}.json",
    output:
        "results/voxels/{rig}/{motion}.h5",
    wildcard_constraints:
        rig=NOT_DEGRADED,
    params:
        cfg=arg(config["voxels"]),
        seed=config["seed"],
        code=code("voxelize"),
    log:
        "results/logs/voxelize/{rig}/{motion}.log",
    group: "per_motion"  # batched into one cluster job per few motions (profiles/slurm)
    threads: 1
    resources:
        mem_mb=by_frames(300, 0.4),
        runtime=by_frames(5, 0.005),
    shell:
        "voxpose voxelize {input.motion} --rig {input.rig} --params {params.cfg} --seed {params.seed}"
        " -o {output} --log {log}"
