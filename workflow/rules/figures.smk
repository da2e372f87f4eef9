# Figure 4 (cross-validation sweeps), a Figure 5-style gallery, per-joint errors and errors over time.


rule figure4:  # lint: no conda/container, see Snakefile
    input:
        [f"{d}/summary.json" for _, _, d in figure4_runs()],
    output:
        png=report("results/figures/figure4.png", caption="../report/figure4.rst", category="Figures"),
        pdf="results/figures/figure4.pdf",
        csv=report("results/tables/figure4.csv", caption="../report/figure4_table.rst", category="1 Tables"),
        meta=report("results/tables/figure4.meta.json", caption="../report/provenance.rst",
                    category="Provenance"),  # fmt: skip
        html=report("results/tables/figure4.html", caption="../report/figure4_table.rst", category="1 Tables"),
    params:
        runs=arg([[label, value, f"{d}/summary.json"] for label, value, d in figure4_runs()]),
        code=code("figure4"),
    log:
        "results/logs/figure4.log",
    localrule: True
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    shell:
        "voxpose figure4 --runs {params.runs} --png {output.png} --pdf {output.pdf} --csv {output.csv}"
        " --html {output.html} --log {log}"


rule gallery:  # lint: no conda/container, see Snakefile
    input:
        predictions=run_file("table2", MPPCA, "predictions.h5"),
        voxels=lambda w: expand("results/voxels/{rig}/{motion}.h5", rig=RIG, motion=EXPERIMENTS["table2"]["test"]),
    output:
        report("results/figures/gallery.png", caption="../report/gallery.rst", category="Figures"),
    params:
        code=code("gallery"),
    log:
        "results/logs/gallery.log",
    threads: 1
    resources:
        mem_mb=by_input(500, 20),
        runtime=by_input(5, 1),
    shell:
        "voxpose gallery {input.predictions} -o {output} --log {log} {input.voxels}"


rule joint_errors:  # lint: no conda/container, see Snakefile
    input:
        table1=run_file("table1", MPPCA, "summary.json"),
        table2=run_file("table2", MPPCA, "summary.json"),
    output:
        report("results/figures/joint_errors.png", caption="../report/joint_errors.rst", category="Figures"),
    params:
        code=code("joint-errors"),
    log:
        "results/logs/joint_errors.log",
    localrule: True
    threads: 1
    resources:
        mem_mb=1000,
        runtime=2,
    shell:
        "voxpose joint-errors --summary 'Table 1 (held-out spiral walk)={input.table1}'"
        " --summary 'Table 2 (five motion types)={input.table2}' -o {output} --log {log}"


rule error_over_time:  # lint: no conda/container, see Snakefile
    input:
        table1=run_file("table1", MPPCA, "predictions.h5"),
        table2=run_file("table2", MPPCA, "predictions.h5"),
    output:
        report("results/figures/error_over_time.png", caption="../report/error_over_time.rst", category="Figures"),
    params:
        code=code("error-over-time"),
    log:
        "results/logs/error_over_time.log",
    localrule: True
    threads: 1
    resources:
        mem_mb=1000,
        runtime=2,
    shell:
        "voxpose error-over-time --predictions 'Table 1, held-out spiral walk={input.table1}'"
        " --predictions 'Table 2, five motion types={input.table2}'"
        " -o {output} --log {log}"
