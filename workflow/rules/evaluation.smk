# Table 1 (one test motion type, MPPCA vs K-means vs Agarwal & Triggs), Table 2 (five motion types at once), the
# per-experiment tables and the subject-held-out (generalisation) table.


rule table1:  # lint: no conda/container, see Snakefile
    input:
        ours=run_file("table1", MPPCA, "summary.json"),
        kmeans=run_file("table1", KMEANS, "summary.json"),
        at_one=run_file("table1", AT_ONE, "summary.json", desc=CTX),
        at_all=run_file("table1", AT_ALL, "summary.json", desc=CTX),
    output:
        csv=report("results/tables/table1.csv", caption="../report/table1.rst", category="Tables"),
        meta=report("results/tables/table1.meta.json", caption="../report/provenance.rst",
                    category="Provenance"),  # fmt: skip
        md="results/tables/table1.md",
    params:
        code=code("table1"),
    log:
        "results/logs/table1.log",
    localrule: True
    threads: 1
    resources:
        mem_mb=500,
        runtime=2,
    shell:
        "voxpose table1 --ours {input.ours} --kmeans {input.kmeans} --at-one {input.at_one} --at-all {input.at_all}"
        " --csv {output.csv} --md {output.md} --log {log}"


rule table2:  # lint: no conda/container, see Snakefile
    input:
        summary=run_file("table2", MPPCA, "summary.json"),
    output:
        csv=report("results/tables/table2.csv", caption="../report/table2.rst", category="Tables"),
        meta=report("results/tables/table2.meta.json", caption="../report/provenance.rst",
                    category="Provenance"),  # fmt: skip
        md="results/tables/table2.md",
    params:
        code=code("table2"),
    log:
        "results/logs/table2.log",
    localrule: True
    threads: 1
    resources:
        mem_mb=500,
        runtime=2,
    shell:
        "voxpose table2 --summary {input.summary} --csv {output.csv} --md {output.md} --log {log}"


rule experiment_table:  # lint: no conda/container, see Snakefile
    input:
        lambda w: [f"{test_dir(w.exp, DESC, feat, s)}/summary.json" for s in TESTS[w.exp] for feat in (MPPCA, KMEANS)],
    output:
        csv=report("results/tables/experiments/{exp}.csv", caption="../report/experiment_table.rst",
                   category="Experiments", subcategory="{exp}"),  # fmt: skip
        meta=report("results/tables/experiments/{exp}.meta.json", caption="../report/provenance.rst",
                    category="Provenance", subcategory="{exp}"),  # fmt: skip
        md="results/tables/experiments/{exp}.md",
    params:
        sets=lambda w: " ".join(
            f"--test-set {s} {test_dir(w.exp, DESC, MPPCA, s)}/summary.json {test_dir(w.exp, DESC, KMEANS, s)}/summary.json"
            for s in TESTS[w.exp]
        ),
        code=code("experiment-table"),
    log:
        "results/logs/experiment_table/{exp}.log",
    localrule: True
    threads: 1
    resources:
        mem_mb=500,
        runtime=2,
    shell:
        "voxpose experiment-table --name {wildcards.exp} {params.sets} --csv {output.csv} --md {output.md} --log {log}"


rule generalisation_table:  # lint: no conda/container, see Snakefile
    input:
        lambda w: [f"{test_dir(held_out(g), DESC, feat)}/summary.json" for g in HELD_OUT for feat in (MPPCA, KMEANS)],
    output:
        csv=report("results/tables/generalisation.csv", caption="../report/generalisation_table.rst",
                   category="Generalisation"),  # fmt: skip
        meta=report("results/tables/generalisation.meta.json", caption="../report/provenance.rst",
                    category="Provenance"),  # fmt: skip
        md="results/tables/generalisation.md",
        png=report("results/figures/generalisation.png", caption="../report/generalisation.rst",
                   category="Generalisation"),  # fmt: skip
    params:
        runs=arg([[g, *(f"{test_dir(held_out(g), DESC, feat)}/summary.json" for feat in (MPPCA, KMEANS))]
                  for g in HELD_OUT]),  # fmt: skip
        code=code("generalisation-table"),
    log:
        "results/logs/generalisation_table.log",
    localrule: True
    threads: 1
    resources:
        mem_mb=1000,
        runtime=2,
    shell:
        "voxpose generalisation-table --runs {params.runs} --csv {output.csv} --md {output.md} --png {output.png} --log {log}"
