# Table 1 (one test motion type, MPPCA vs K-means vs Agarwal & Triggs), Table 2 (five motion types at once), the
# per-experiment tables and the subject-held-out (generalisation) table.


rule table1:  # lint: no conda/container, see Snakefile
    input:
        ours=run_pair("table1", MPPCA),
        kmeans=run_pair("table1", KMEANS),
        at_one=run_pair("table1", AT_ONE, desc=CTX),
        at_all=run_pair("table1", AT_ALL, desc=CTX),
    output:
        csv=report("results/tables/table1.csv", caption="../report/table1.rst", category="1 Tables",
                   labels={"table": "Table 1", "file": "CSV"}),  # fmt: skip
        meta=report("results/tables/table1.meta.json", caption="../report/provenance.rst",
                    category="Provenance"),  # fmt: skip
        md="results/tables/table1.md",
        html=report("results/tables/table1.html", caption="../report/table1.rst", category="1 Tables",
                    labels={"table": "Table 1", "file": "table"}),  # fmt: skip
    params:
        boot=bootstrap_args(),
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
        " {params.boot} --csv {output.csv} --md {output.md} --html {output.html} --log {log}"


rule table2:  # lint: no conda/container, see Snakefile
    input:
        run=run_pair("table2", MPPCA),
    output:
        csv=report("results/tables/table2.csv", caption="../report/table2.rst", category="1 Tables",
                   labels={"table": "Table 2", "file": "CSV"}),  # fmt: skip
        meta=report("results/tables/table2.meta.json", caption="../report/provenance.rst",
                    category="Provenance"),  # fmt: skip
        md="results/tables/table2.md",
        html=report("results/tables/table2.html", caption="../report/table2.rst", category="1 Tables",
                    labels={"table": "Table 2", "file": "table"}),  # fmt: skip
    params:
        boot=bootstrap_args(),
        code=code("table2"),
    log:
        "results/logs/table2.log",
    localrule: True
    threads: 1
    resources:
        mem_mb=500,
        runtime=2,
    shell:
        "voxpose table2 --run {input.run} {params.boot} --csv {output.csv} --md {output.md} --html {output.html}"
        " --log {log}"


rule paper_claims:  # lint: no conda/container, see Snakefile
    input:
        table1_mppca=run_file("table1", MPPCA, "predictions.h5"),
        table1_kmeans=run_file("table1", KMEANS, "predictions.h5"),
        table1_at_one=run_file("table1", AT_ONE, "predictions.h5", desc=CTX),
        table1_at_all=run_file("table1", AT_ALL, "predictions.h5", desc=CTX),
        table2_mppca=run_file("table2", MPPCA, "predictions.h5"),
        table2_kmeans=run_file("table2", KMEANS, "predictions.h5"),
    output:
        csv=report("results/tables/claims.csv", caption="../report/claims.rst", category="1 Tables",
                   labels={"table": "The paper's claims", "file": "CSV"}),  # fmt: skip
        html=report("results/tables/claims.html", caption="../report/claims.rst", category="1 Tables",
                    labels={"table": "The paper's claims", "file": "table"}),  # fmt: skip
        meta=report("results/tables/claims.meta.json", caption="../report/provenance.rst",
                    category="Provenance"),  # fmt: skip
    params:
        runs=lambda w, input: " ".join(f"--run {name} {path}" for name, path in input.items()),
        data=shlex.quote(data_set()),
        boot=bootstrap_args(),
        code=code("paper-claims"),
    log:
        "results/logs/paper_claims.log",
    localrule: True
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    shell:
        "voxpose paper-claims {params.runs} --data-set {params.data} {params.boot} --csv {output.csv}"
        " --html {output.html} --log {log}"


rule report_summary:  # lint: no conda/container, see Snakefile
    input:
        table1="results/tables/table1.csv",
        table2="results/tables/table2.csv",
        figure4="results/tables/figure4.csv",
        figure4_png="results/figures/figure4.png",
        claims="results/tables/claims.csv",
    output:
        report("results/report/summary.html", caption="../report/summary.rst", category="0 Summary",
               labels={"page": "Tables 1-2, Figure 4, claims, run"}),  # fmt: skip
    params:
        data=shlex.quote(data_set()),
        boot=config["report"]["bootstrap"],
        code=code("report-summary"),
    log:
        "results/logs/report_summary.log",
    localrule: True
    threads: 1
    resources:
        mem_mb=1000,
        runtime=2,
    shell:
        "voxpose report-summary --table1 {input.table1} --table2 {input.table2} --figure4 {input.figure4}"
        " --figure4-png {input.figure4_png} --claims {input.claims}"
        " --data-set {params.data} --bootstrap {params.boot} -o {output} --log {log}"


rule experiment_table:  # lint: no conda/container, see Snakefile
    input:
        lambda w: [f"{test_dir(w.exp, DESC, feat, s)}/summary.json" for s in TESTS[w.exp] for feat in (MPPCA, KMEANS)],
    output:
        csv=report("results/tables/experiments/{exp}.csv", caption="../report/experiment_table.rst",
                   category="Experiments", subcategory="{exp}"),  # fmt: skip
        meta=report("results/tables/experiments/{exp}.meta.json", caption="../report/provenance.rst",
                    category="Provenance", subcategory="{exp}"),  # fmt: skip
        md="results/tables/experiments/{exp}.md",
        html=report("results/tables/experiments/{exp}.html", caption="../report/experiment_table.rst",
                    category="Experiments", subcategory="{exp}"),  # fmt: skip
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
        "voxpose experiment-table --name {wildcards.exp} {params.sets} --csv {output.csv} --md {output.md}"
        " --html {output.html} --log {log}"


rule generalisation_table:  # lint: no conda/container, see Snakefile
    input:
        lambda w: [f"{test_dir(held_out(g), DESC, feat)}/{name}" for g in HELD_OUT for feat in (MPPCA, KMEANS)
                   for name in ("summary.json", "predictions.h5")],  # fmt: skip
    output:
        csv=report("results/tables/generalisation.csv", caption="../report/generalisation_table.rst",
                   category="Generalisation"),  # fmt: skip
        meta=report("results/tables/generalisation.meta.json", caption="../report/provenance.rst",
                    category="Provenance"),  # fmt: skip
        md="results/tables/generalisation.md",
        png=report("results/figures/generalisation.png", caption="../report/generalisation.rst",
                   category="Generalisation"),  # fmt: skip
        html=report("results/tables/generalisation.html", caption="../report/generalisation_table.rst",
                    category="Generalisation"),  # fmt: skip
    params:
        boot=bootstrap_args(),
        runs=arg([[g, *(f"{test_dir(held_out(g), DESC, feat)}/{name}" for name in ("summary.json", "predictions.h5")
                        for feat in (MPPCA, KMEANS))] for g in HELD_OUT]),  # fmt: skip
        code=code("generalisation-table"),
    log:
        "results/logs/generalisation_table.log",
    localrule: True
    threads: 1
    resources:
        mem_mb=1000,
        runtime=2,
    shell:
        "voxpose generalisation-table --runs {params.runs} {params.boot} --csv {output.csv} --md {output.md}"
        " --png {output.png} --html {output.html} --log {log}"
