# 3D shape contexts at the basis voxels over the surface voxels (Section 4), one cached file per parameter set.


rule describe:
    input:
        "results/voxels/{rig}/{motion}.h5",
    output:
        "results/descriptors/{rig}/{desc}/{motion}.h5",
    params:
        cfg=lambda w: arg(DESCRIPTORS[w.desc]),
        code=code("shape_context", "shape_context_lut", "store"),
    log:
        "results/logs/describe/{rig}/{desc}/{motion}.log",
    threads: 2  # frames are described by a thread pool (numpy and scipy release the GIL)
    resources:
        mem_mb=2000,
        runtime=lambda w, input: 5 + int(input.size_mb),
    shell:
        "voxpose describe {input} --params {params.cfg} -o {output} --log {log} --threads {threads}"
