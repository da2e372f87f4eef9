# 3D shape contexts at the basis voxels over the surface voxels (Section 4), one cached file per parameter set.


rule describe:  # lint: no conda/container, see Snakefile
    input:
        "results/voxels/{rig}/{motion}.h5",
    output:
        "results/descriptors/{rig}/{desc}/{motion}.h5",
    params:
        cfg=lambda w: arg(DESCRIPTORS[w.desc]),
        code=code("describe"),
    log:
        "results/logs/describe/{rig}/{desc}/{motion}.log",
    group: "per_motion"  # batched into one cluster job per few motions (profiles/slurm)
    threads: 1  # motions are described side by side; `voxpose describe --threads N` pools frames instead
    resources:
        mem_mb=by_frames(300, 1.2),  # profiles/README.md
        runtime=by_frames(5, 0.005),
    shell:
        "voxpose describe {input} --params {params.cfg} -o {output} --log {log} --threads {threads}"
