# Motion capture in: BVH files (generated, derived or the user's) -> canonical poses per motion (Section 2).


rule generate_bvh:  # lint: no conda/container, see Snakefile
    output:
        "results/bvh/generated/{motion}.bvh",
    params:
        spec=lambda w: GENERATED[w.motion],
        seed=config["seed"],
        code=code("generate"),
    log:
        "results/logs/generate_bvh/{motion}.log",
    group: "per_motion"  # batched into one cluster job per few motions (profiles/slurm)
    threads: 1
    resources:
        mem_mb=by_frames(250, 0.1),
        runtime=by_frames(2, 0.01),
    shell:
        "voxpose generate --kind {params.spec[0]} --index {params.spec[1]} --frames {params.spec[2]}"
        " --seed {params.seed} -o {output} --log {log}"


rule derive_bvh:  # lint: no conda/container, see Snakefile
    input:
        lambda w: SOURCE_BVH[DERIVED[w.motion][1]],
    output:
        "results/bvh/derived/{motion}.bvh",
    params:
        kind=lambda w: DERIVED[w.motion][0],
        cfg=lambda w: arg(DERIVED[w.motion][2]),
        seed=config["seed"],
        code=code("derive"),
    log:
        "results/logs/derive_bvh/{motion}.log",
    group: "per_motion"  # batched into one cluster job per few motions (profiles/slurm)
    threads: 1
    resources:
        mem_mb=by_frames(250, 0.2),
        runtime=by_frames(2, 0.01),
    shell:
        "voxpose derive --kind {params.kind} --params {params.cfg} --seed {params.seed} {input} -o {output} --log {log}"


rule motion:  # lint: no conda/container, see Snakefile
    input:
        bvh_path,
    output:
        "results/motions/{motion}.h5",
    params:
        cfg=lambda w: arg(wc.motion_settings(w.motion, config["motions"])),  # the motion's own: overrides
        code=code("motion"),
    log:
        "results/logs/motion/{motion}.log",
    group: "per_motion"  # batched into one cluster job per few motions (profiles/slurm)
    threads: 1
    resources:
        mem_mb=by_frames(200, 0.1),
        runtime=by_frames(2, 0.01),
    shell:
        "voxpose motion {input} -o {output} --params {params.cfg} --log {log}"
